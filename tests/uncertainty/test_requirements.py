"""Requirement statistics: Wilks sample sizes, order-statistic percentile bounds, proportion
intervals against scipy.stats, and requirement tables (met / not met / inconclusive)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from adcskit.errors import ConfigError, InputError
from adcskit.uncertainty import (
    Requirement,
    check_requirements,
    exceedance_probability,
    parse_requirement,
    percentile_bound,
    proportion_interval,
    read_requirements,
    samples_needed,
)

# ------------------------------------------------------------------------------ sample sizes


def test_wilks_published_sample_sizes():
    # Wilks 1941 (Ann. Math. Statist. 12, 91-96): 59 samples for 95 % coverage at 95 %
    # confidence, one-sided, no failure; 93 two-sided. Guba, Makai & Pal 2003 (Reliab. Eng.
    # Syst. Safety 80, 217-232), Table 1: 59, 93, 124, 153, 181 one-sided with 0..4 failures;
    # two-sided (r on each side) 93, 153, 208. Integers: exact.
    assert [samples_needed(0.95, 0.95, failures=r) for r in range(5)] == [59, 93, 124, 153, 181]
    assert [samples_needed(0.95, 0.95, failures=r, side="two-sided") for r in range(3)] == [93, 153, 208]
    # the other textbook pairs: 90/90 -> 22, 99/99 -> 459, 99/95 -> 299 (Guba et al. 2003, Table 1)
    assert samples_needed(0.90, 0.90) == 22
    assert samples_needed(0.99, 0.99) == 459
    assert samples_needed(0.99, 0.95) == 299


@pytest.mark.parametrize(("beta", "gamma"), [(0.95, 0.95), (0.9, 0.99), (0.999, 0.9), (0.5, 0.5)])
def test_zero_failure_closed_form(beta, gamma):
    # r = 0: 1 - beta**n >= gamma  <=>  n >= ln(1 - gamma) / ln(beta) (Wilks 1941, eq. 8)
    n = samples_needed(beta, gamma)
    assert n == math.ceil(math.log(1 - gamma) / math.log(beta) - 1e-12)


@pytest.mark.parametrize("r", [0, 1, 3, 10])
def test_sample_size_is_minimal_against_beta_law(r):
    # independent oracle: the coverage of X_(n-r) follows Beta(n - r, r + 1) (Wilks 1941), so
    # the confidence that it covers beta is 1 - beta.cdf(beta, n - r, r + 1).
    beta, gamma = 0.97, 0.9
    n = samples_needed(beta, gamma, failures=r)
    conf = lambda m: stats.beta.sf(beta, m - r, r + 1)  # noqa: E731
    assert conf(n) >= gamma > conf(n - 1)
    # two-sided [X_(1+r), X_(n-r)]: coverage Beta(n - 2r - 1, 2r + 2)
    n2 = samples_needed(beta, gamma, failures=r, side="two-sided")
    conf2 = lambda m: stats.beta.sf(beta, m - 2 * r - 1, 2 * r + 2)  # noqa: E731
    assert conf2(n2) >= gamma > conf2(n2 - 1)


@settings(max_examples=40, deadline=None)
@given(st.floats(0.5, 0.995), st.floats(0.5, 0.995), st.integers(0, 5))
def test_sample_size_monotone(beta, gamma, r):
    n = samples_needed(beta, gamma, failures=r)
    assert samples_needed(min(beta + 0.004, 0.999), gamma, failures=r) >= n
    assert samples_needed(beta, min(gamma + 0.004, 0.999), failures=r) >= n
    assert samples_needed(beta, gamma, failures=r + 1) > n
    assert samples_needed(beta, gamma, failures=r, side="two-sided") >= n


# ------------------------------------------------------------------------ percentile bounds


def test_percentile_bound_ranks_against_binomial():
    # Conover 1999 sec. 3.2: the upper bound is X_(k), k the smallest rank with
    # P(Binom(n, p) <= k - 1) >= gamma; the lower one the largest k with P(Binom >= k) >= gamma.
    x = np.random.default_rng(3).normal(size=400)
    n, q, g = 400, 0.9, 0.95
    up = percentile_bound(x, 90.0, confidence=g)
    lo = percentile_bound(x, 90.0, confidence=g, side="lower")
    cdf = lambda j: stats.binom.cdf(j, n, q)  # noqa: E731
    assert cdf(up.rank_upper - 1) >= g > cdf(up.rank_upper - 2)
    assert 1 - cdf(lo.rank_lower - 1) >= g > 1 - cdf(lo.rank_lower)
    xs = np.sort(x)
    assert up.upper == xs[up.rank_upper - 1] and lo.lower == xs[lo.rank_lower - 1]
    assert up.achieved_confidence == pytest.approx(cdf(up.rank_upper - 1), abs=1e-15)
    two = percentile_bound(x, 90.0, confidence=0.9, side="two-sided")
    assert (two.rank_lower, two.rank_upper) == (lo.rank_lower, up.rank_upper)  # alpha/2 = 0.05 per side
    assert two.achieved_confidence == pytest.approx(cdf(up.rank_upper - 1) - cdf(lo.rank_lower - 1), abs=1e-15)
    assert two.lower <= two.estimate <= two.upper


def test_percentile_bound_wilks_59():
    # 59 samples: the largest is a 95 % upper bound on the p95 (Wilks 1941); 58 are too few.
    b = percentile_bound(np.arange(59.0), 95.0, confidence=0.95)
    assert b.success and b.rank_upper == 59 and b.achieved_confidence == pytest.approx(1 - 0.95**59, rel=1e-12)
    short = percentile_bound(np.arange(58.0), 95.0, confidence=0.95)
    assert not short.success and short.upper == math.inf and short.rank_upper is None
    assert short.n_needed == 59 and "at least 59 needed" in short.message
    assert math.isnan(short.achieved_confidence)


def test_percentile_bound_coverage_monte_carlo():
    # seeded coverage check: for a continuous law the bound covers with probability exactly
    # achieved_confidence (a binomial probability); 4000 replicates -> sigma <= 0.008, 4 sigma.
    rng = np.random.default_rng(7)
    n, p, g, reps = 120, 90.0, 0.9, 4000
    sample = np.sort(rng.exponential(size=(reps, n)), axis=1)
    b = percentile_bound(sample[0], p, confidence=g)
    true_q = -math.log(1 - p / 100)  # exponential(1) quantile
    covered = np.mean(sample[:, b.rank_upper - 1] >= true_q)
    sigma = math.sqrt(b.achieved_confidence * (1 - b.achieved_confidence) / reps)
    assert abs(covered - b.achieved_confidence) < 4 * sigma
    assert b.achieved_confidence >= g


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=300), st.sampled_from([5.0, 50.0, 90.0, 99.0]),
       st.floats(0.5, 0.999))
def test_percentile_bounds_ordering(values, p, g):
    x = np.asarray(values)
    two = percentile_bound(x, p, confidence=g, side="two-sided")
    up = percentile_bound(x, p, confidence=g)
    lo = percentile_bound(x, p, confidence=g, side="lower")
    assert lo.lower <= up.upper and two.lower <= lo.lower and up.upper <= two.upper  # wider two-sided
    if two.success:
        assert two.rank_lower <= two.rank_upper and two.achieved_confidence >= g - 1e-12
    if up.success:
        assert up.achieved_confidence >= g - 1e-12
        # more confidence never gives a tighter bound
        assert percentile_bound(x, p, confidence=min(g + 0.0005, 0.9999)).upper >= up.upper
    assert up.success == (x.size >= up.n_needed)


def test_percentile_bound_rejects():
    with pytest.raises(InputError, match="NaN"):
        percentile_bound([1.0, np.nan], 50.0)
    with pytest.raises(InputError, match="percentile"):
        percentile_bound([1.0, 2.0], 100.0)
    with pytest.raises(InputError, match="side"):
        percentile_bound([1.0, 2.0], 50.0, side="both")
    with pytest.raises(InputError, match="1-D"):
        percentile_bound([[1.0, 2.0]], 50.0)


# ------------------------------------------------------------------------------- proportions


@pytest.mark.parametrize(("k", "n"), [(0, 59), (3, 100), (50, 50), (7, 1000), (1, 1)])
@pytest.mark.parametrize("g", [0.9, 0.95, 0.99])
def test_clopper_pearson_against_beta_quantiles(k, n, g):
    # Clopper & Pearson 1934: [B(a/2; k, n-k+1), B(1-a/2; k+1, n-k)], ends 0 / 1 at k = 0 / n
    a = 1 - g
    ci = proportion_interval(k, n, confidence=g)
    lo = 0.0 if k == 0 else stats.beta.ppf(a / 2, k, n - k + 1)
    hi = 1.0 if k == n else stats.beta.ppf(1 - a / 2, k + 1, n - k)
    assert ci.lower == pytest.approx(lo, rel=1e-9, abs=1e-14) and ci.upper == pytest.approx(hi, rel=1e-9)
    one = proportion_interval(k, n, confidence=g, side="upper")
    assert one.lower == 0.0
    assert one.upper == pytest.approx(1.0 if k == n else stats.beta.ppf(g, k + 1, n - k), rel=1e-9)
    low = proportion_interval(k, n, confidence=g, side="lower")
    assert low.upper == 1.0 and low.lower == pytest.approx(0.0 if k == 0 else stats.beta.ppf(1 - g, k, n - k + 1),
                                                           rel=1e-9, abs=1e-14)


def test_zero_failures_in_59_runs():
    # 0 of n: the one-sided exact bound is 1 - (1 - gamma)**(1/n); 59 runs -> 0.0495 < 5 %
    ci = proportion_interval(0, 59, side="upper")
    assert ci.upper == pytest.approx(1 - 0.05 ** (1 / 59), rel=1e-12) and ci.upper < 0.05


@pytest.mark.parametrize(("k", "n"), [(0, 20), (3, 100), (17, 40)])
def test_wilson_against_closed_form(k, n):
    # Wilson 1927: (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n), z = Phi^-1(1 - a/2)
    z = stats.norm.ppf(0.975)
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    ci = proportion_interval(k, n, method="wilson")
    assert ci.lower == pytest.approx(max(c - h, 0.0), abs=1e-12) and ci.upper == pytest.approx(c + h, rel=1e-12)
    ref = stats.binomtest(k, n).proportion_ci(0.95, method="wilson")
    assert (ci.lower, ci.upper) == (pytest.approx(ref.low), pytest.approx(ref.high))


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 2000), st.floats(0, 1), st.floats(0.5, 0.99), st.sampled_from(["clopper-pearson", "wilson"]))
def test_proportion_interval_properties(n, frac, g, method):
    k = int(round(frac * n))
    ci = proportion_interval(k, n, confidence=g, method=method)
    wide = proportion_interval(k, n, confidence=min(g + 0.009, 0.999), method=method)
    assert 0.0 <= ci.lower <= ci.estimate <= ci.upper <= 1.0
    assert wide.lower <= ci.lower + 1e-12 and wide.upper >= ci.upper - 1e-12  # nested in the confidence


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 40), st.floats(0.001, 0.999), st.floats(0.8, 0.99))
def test_clopper_pearson_exact_coverage(n, p, g):
    # Clopper & Pearson 1934: the exact interval covers the true p with probability >= g for every
    # p and n; the coverage is the binomial sum over the k whose interval holds p (no sampling).
    inside = [(c := proportion_interval(k, n, confidence=g)).lower <= p <= c.upper for k in range(n + 1)]
    assert stats.binom.pmf(np.arange(n + 1), n, p) @ np.array(inside, float) >= g - 1e-9


def test_exceedance_probability_counts():
    x = np.array([0.0, 0.1, 0.2, 0.3, np.inf])
    assert exceedance_probability(x, 0.2).k == 2
    assert exceedance_probability(x, 0.2, comparison=">=").k == 3
    assert exceedance_probability(x, 0.1, comparison="<").k == 1
    pe = exceedance_probability(x, 0.2, side="upper", method="wilson")
    ref = stats.binomtest(2, 5, alternative="less").proportion_ci(0.95, method="wilson")
    assert pe.upper == pytest.approx(ref.high) and pe.event == "x > 0.2"


# -------------------------------------------------------------------------------- requirements


@pytest.mark.parametrize("text", [
    "pointing_max_deg p99 <= 0.1 after 300 s",
    "pointing_rms_deg p99.9 < 0.05 at 90 % confidence",
    "ADCS-7: settling_time_s max <= 120",
    "margin_deg min > 0",
    "knowledge_rms_deg mean <= 0.01 after 50 s at 99 %",
    "P(pointing_max_deg > 0.1) <= 0.001",
    "R3: P(final_error_deg >= 0.5) < 2 % after 10 s",
])
def test_requirement_text_round_trip(text):
    r = parse_requirement(text)
    assert parse_requirement(r.text) == r
    assert read_requirements([r.text]) == (r,)


@settings(max_examples=50, deadline=None)
@given(st.sampled_from(["percentile", "mean", "max", "min", "probability"]), st.floats(-1e6, 1e6),
       st.floats(0.001, 99.999), st.floats(0.5, 0.9999), st.one_of(st.none(), st.floats(0, 1e5)),
       st.sampled_from(["<=", "<"]))
def test_requirement_text_round_trip_property(stat, value, pct, conf, after, op):
    # 12 significant digits in the text: the parsed requirement equals the original to 1e-11 rel.
    kw = dict(metric="pointing_max_deg", statistic=stat, comparison=op if stat != "min" else ">=",
              threshold=value if stat != "probability" else pct / 100, confidence=conf, after_s=after)
    if stat == "percentile":
        kw["percentile"] = pct
    if stat == "probability":
        kw.update(event=">", event_threshold=value)
    r = Requirement(**kw)
    back = parse_requirement(r.text)
    for f in ("threshold", "percentile", "event_threshold", "confidence", "after_s"):
        a, b = getattr(r, f), getattr(back, f)
        assert (a is None and b is None) or b == pytest.approx(a, rel=1e-11, abs=1e-300)
    assert (back.metric, back.statistic, back.comparison, back.event) == (r.metric, r.statistic, r.comparison, r.event)


def test_parse_requirement_fields():
    r = parse_requirement("pointing_max_deg p99 <= 0.1 after 300 s")
    assert r == Requirement(metric="pointing_max_deg", statistic="percentile", percentile=99.0, comparison="<=",
                            threshold=0.1, after_s=300.0)
    pr = parse_requirement("P(settling_time_s > 60) <= 1 %", confidence=0.9)
    assert (pr.statistic, pr.event, pr.event_threshold, pr.threshold, pr.confidence) == \
        ("probability", ">", 60.0, 0.01, 0.9)


@pytest.mark.parametrize(("text", "match"), [
    ("pointing p99 0.1", "text must read"),
    ("pointing p100 <= 0.1", "percentile"),
    ("pointing max >= 0.1", "comparison"),
    ("pointing min <= 0.1", "comparison"),
    ("P(x > 1) <= 1.5", "threshold"),
    ("x p99 <= 1 at 40 %", "confidence"),
])
def test_parse_requirement_rejects(text, match):
    with pytest.raises(InputError, match=match):
        parse_requirement(text)


def test_requirement_fields_checked():
    with pytest.raises(InputError, match="percentile must be given"):
        Requirement(metric="x", statistic="percentile", comparison="<=", threshold=1.0)
    with pytest.raises(InputError, match="event"):
        Requirement(metric="x", statistic="probability", comparison="<=", threshold=0.1)
    with pytest.raises(InputError, match="percentile must be None"):
        Requirement(metric="x", statistic="mean", comparison="<=", threshold=1.0, percentile=5.0)


def test_read_requirements_toml(tmp_path):
    path = tmp_path / "req.toml"
    path.write_text('[[requirement]]\nname = "ADCS-1"\ntext = "pointing_max_deg p99 <= 0.1 after 300 s"\n'
                    '[[requirement]]\nmetric = "settling_time_s"\nstatistic = "probability"\nevent = ">"\n'
                    'event_threshold = 60.0\ncomparison = "<="\nthreshold = 0.01\nconfidence = 0.9\n')
    a, b = read_requirements(path)
    assert a.name == "ADCS-1" and a.after_s == 300.0 and a.confidence == 0.95
    assert b.text == "P(settling_time_s > 60) <= 0.01 at 90 % confidence"
    path.write_text('[[requirement]]\nmetric = "x"\nstatistic = "max"\ncomparison = "<="\nthreshold = 1\nunit = "deg"\n')
    with pytest.raises(ConfigError, match="unknown key"):
        read_requirements(path)
    with pytest.raises(ConfigError, match="requirement"):
        read_requirements({"requirements": []})
    with pytest.raises(InputError, match="at least one"):
        read_requirements([])


def _metrics(rng_seed=1, n=500):
    # the closed-loop simulator's metric names (adcskit.simulation.METRIC_NAMES), synthetic values
    rng = np.random.default_rng(rng_seed)
    return {"pointing_max_deg": rng.rayleigh(0.02, n), "pointing_rms_deg": rng.rayleigh(0.01, n),
            "settling_time_s": rng.normal(40.0, 5.0, n)}


def test_verdicts_are_symmetric_and_bound_based():
    m = _metrics()
    p99 = np.quantile(m["pointing_max_deg"], 0.99)
    table = check_requirements([
        "pointing_max_deg p99 <= 0.1",                  # far above: met
        "pointing_max_deg p99 <= 0.02",                 # far below: not met
        f"pointing_max_deg p99 <= {p99 * 1.02:.6f}",     # point estimate meets it, bound does not
        "pointing_max_deg p1 >= 0.0001",                 # lower-side requirement, met
        "settling_time_s mean <= 41",
        "settling_time_s mean >= 41",
    ], m)
    out = [r.outcome for r in table.rows]
    assert out == ["met", "not met", "inconclusive", "met", "met", "not met"]
    inc = table.rows[2]
    assert inc.estimate <= 1.02 * p99 < inc.bound and inc.n_needed is not None and inc.n_needed > 500
    assert inc.verdict == f"inconclusive (need ~{inc.n_needed} samples)"
    assert (table.n_met, table.n_not_met, table.n_inconclusive, table.success) == (3, 2, 1, False)


def test_mean_bound_against_scipy_ttest():
    x = _metrics()["settling_time_s"]
    row = check_requirements(["settling_time_s mean <= 41 at 90 %"], {"settling_time_s": x}).rows[0]
    ci = stats.ttest_1samp(x, 0.0, alternative="less").confidence_interval(0.9)
    assert row.bound == pytest.approx(ci.high, rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 400), st.floats(0.0, 1.0), st.sampled_from([90.0, 95.0, 99.0]), st.floats(0.5, 0.99))
def test_percentile_verdict_dual_to_exact_binomial(n, frac, p, g):
    # duality (Conover 1999 sec. 3.2): X_(k) <= T  <=>  #(X > T) <= n - k, so "upper order-statistic
    # bound on the p-th percentile <= T" is "Clopper-Pearson upper bound on P(X > T) <= 1 - p"
    k_bad = int(round(frac * n))
    x = np.concatenate([np.full(n - k_bad, 0.5), np.full(k_bad, 2.0)])
    by_pct = check_requirements([f"x p{p:g} <= 1 at {g * 100:.6g} %"], {"x": x}).rows[0]
    by_prob = check_requirements([f"P(x > 1) <= {1 - p / 100:.6g} at {g * 100:.6g} %"], {"x": x}).rows[0]
    assert by_pct.outcome == by_prob.outcome


def test_n_needed_decides_at_the_observed_rate():
    # planning number: with n_needed samples and the observed violation rate, the bound decides
    x = np.r_[np.zeros(496), np.ones(4)]            # 0.8 % violate; requirement 1 %
    row = check_requirements(["P(x > 0.5) <= 0.01"], {"x": x}).rows[0]
    assert row.outcome == "inconclusive" and row.n_needed is not None
    big = row.n_needed
    kk = math.ceil(0.008 * big)
    assert check_requirements(["P(x > 0.5) <= 0.01"], {"x": np.r_[np.zeros(big - kk), np.ones(kk)]}).rows[0].outcome == "met"
    x = np.r_[np.zeros(99), np.ones(1)]             # 1 % exactly at a 1 % requirement: nothing decides it
    row = check_requirements(["P(x > 0.5) <= 0.01"], {"x": x}).rows[0]
    assert row.outcome == "inconclusive" and row.n_needed is None and row.verdict == "inconclusive"


def test_max_is_every_sample():
    rows = check_requirements(["x max <= 1", "x max < 0.9", "x min >= 0"], {"x": np.linspace(0, 0.9, 59)}).rows
    assert [r.outcome for r in rows] == ["met", "not met", "met"]
    assert "95.05 %" in rows[0].detail  # 59 samples: 0.05**(1/59) = 95.05 % coverage at 95 % (Wilks 1941)


def test_time_window_must_match():
    m = _metrics()
    req = ["pointing_max_deg p99 <= 0.1 after 300 s"]
    assert check_requirements(req, m, metrics_from_s=300.0).rows[0].outcome == "met"
    assert check_requirements(req, m, metrics_from_s={"pointing_max_deg": 300}).rows[0].outcome == "met"
    with pytest.raises(InputError, match="window .* unknown"):
        check_requirements(req, m)
    with pytest.raises(InputError, match="cannot be re-windowed"):
        check_requirements(req, m, metrics_from_s=50.0)
    with pytest.raises(InputError, match="window .* unknown"):
        check_requirements(req, m, metrics_from_s={"pointing_rms_deg": 300.0})
    with pytest.raises(InputError, match="must be one of"):
        check_requirements(["pointing_error_deg p99 <= 0.1"], m)


def test_nan_policy():
    x = np.r_[np.full(99, 10.0), np.nan]              # settling_time_s: NaN = never settled
    with pytest.raises(InputError, match="nan_policy"):
        check_requirements(["settling_time_s max <= 60"], {"settling_time_s": x})
    rows = check_requirements(["settling_time_s max <= 60", "P(settling_time_s > 60) <= 0.05",
                               "P(settling_time_s <= 60) >= 0.5"], {"settling_time_s": x}, nan_policy="fail").rows
    assert rows[0].outcome == "not met" and rows[0].n_nan == 1
    assert rows[1].n_violating == 1 and rows[2].n_violating == 99  # NaN never counts in the requirement's favour
    with pytest.raises(InputError, match="mean"):
        check_requirements(["settling_time_s mean <= 60"], {"settling_time_s": x}, nan_policy="fail")


def test_table_rows_and_to_dict():
    table = check_requirements(["ADCS-1: pointing_max_deg p99 <= 0.1", "pointing_rms_deg p99 <= 0.001"], _metrics(n=100))
    rows = table.table_rows()
    assert [list(r) for r in rows] == [list(table.columns)] * 2
    assert rows[0]["name"] == "ADCS-1" and rows[0]["requirement"].startswith("pointing_max_deg p99")
    d = json.loads(json.dumps(table.to_dict()))
    assert d["rows"][1]["outcome"] == "not met" and d["rows"][0]["spec"]["percentile"] == 99.0
