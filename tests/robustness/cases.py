"""The registry of valid calls of the robustness suite: one entry per public callable.

HOW TO ADD AN ENTRY (a new public function, class or method):

    @case("estimation.my_function", positive=("dt",))
    def _():
        return dict(x=[1.0, 2.0, 3.0], dt=0.1, method="fast")

The decorated function returns the keyword arguments of ONE valid, fast (< ~50 ms) call; it is
called afresh for every mutation. The name is ``"<subpackage>.<name in its __all__>"``
(``".method"`` may follow for a method; pass ``target=`` to build the bound method). Every
argument present in the dict is mutated according to its inferred kind (float, int, flag,
choice (str), array, mapping, callable, object); override with ``kinds={"arg": "times"}`` or
``kinds={"arg": "skip"}``. See :class:`harness.Case` for ``positive``, ``degenerate``,
``nonfinite_ok``, ``nan_ok``, ``aliases``, ``extra`` and ``slow``. Names that are not callables
with a meaningful valid call (result dataclasses, exception types) go into ``EXEMPT`` with a
reason. ``test_every_public_name_has_an_entry`` fails for a public name in neither.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from harness import Case

CASES: dict[str, Case] = {}

#: The one directory under which every file or directory a valid call needs is created (a
#: factory runs afresh for every mutation, hundreds of times per run). Made on first use —
#: factories also run at collection time, before any fixture — and removed by
#: :func:`remove_scratch` at the end of the pytest session (``conftest.py``), so a run leaves
#: nothing behind in the temporary directory.
_SCRATCH: list[str] = []


def scratch_path(prefix: str, *, file_suffix: str | None = None) -> str:
    """A fresh directory (or, with ``file_suffix``, an empty file) under the suite's scratch root."""
    import atexit
    import os
    import tempfile

    if not _SCRATCH:
        _SCRATCH.append(tempfile.mkdtemp(prefix="adcskit-rob-"))
        atexit.register(remove_scratch)  # outside pytest too
    if file_suffix is None:
        return tempfile.mkdtemp(prefix=prefix, dir=_SCRATCH[0])
    fd, path = tempfile.mkstemp(prefix=prefix, suffix=file_suffix, dir=_SCRATCH[0])
    os.close(fd)
    return path


def remove_scratch() -> None:
    """Delete the scratch root and everything the valid calls wrote there."""
    import shutil

    while _SCRATCH:
        shutil.rmtree(_SCRATCH.pop(), ignore_errors=True)


def case(name: str, **opts: Any) -> Callable[[Callable[[], dict[str, Any]]], Callable[[], dict[str, Any]]]:
    """Register the decorated valid-call factory under ``name``."""

    def deco(factory: Callable[[], dict[str, Any]]) -> Callable[[], dict[str, Any]]:
        if name in CASES:
            raise KeyError(f"duplicate robustness case {name!r}")
        CASES[name] = Case(name=name, valid=factory, **opts)
        return factory

    return deco


def method(cls_path: str, make: Callable[[], Any], meth: str) -> Callable[[], Callable[..., Any]]:
    """``target=`` for a method of an instance built by ``make``."""
    return lambda: getattr(make(), meth)


#: Public names without an entry, with the reason. Exception types are exempt automatically.
EXEMPT: dict[str, str] = {}


def exempt(reason: str, *names: str) -> None:
    for n in names:
        EXEMPT[n] = reason


RESULT = "result dataclass: built by adcskit from validated data, not an entry point"
exempt(
    RESULT,
    "dynamics.AttitudeTrajectory",
    "environment.OrbitState",
    "determination.WahbaResult",
    "determination.RobustWahbaResult",
    "estimation.AugmentedEKFResult",
    "estimation.IdentificationResult",
    "estimation.JointResult",
    "estimation.KalmanResult",
    "estimation.LinearSimulation",
    "optimal_control.BangBangResult",
    "optimal_control.MeshSequenceResult",
    "optimal_control.MultistartResult",
    "optimal_control.OptimalControlSolution",
    "optimal_control.ResimulationResult",
    "thrusters.AllocationResult",
    "thrusters.Controllability",
    "thrusters.LayoutResult",
    "thrusters.LayoutScore",
    "control.OnOffMetrics",
    "control.OnOffTrace",
    "uncertainty.CampaignResult",
    "uncertainty.SampleStats",
    "studies.StudyResult",
    "studies.Check",
    "studies.Comparison",
    "estimation.MEKFResult",
    "sensors.GyroMeasurement",
    "studies.Reading",
    "studies.Claim",
    "studies.Finding",
)
exempt(
    "raw NLP point (primal/dual) kept in a solution for warm starts: built by solve from its own "
    "CasADi output, not an entry point",
    "optimal_control.NLPPoint",
)
exempt("abstract base class with no behaviour of its own", "uncertainty.Executor")
exempt(
    "study registry record and figure helper: owned by the studies framework, exercised by "
    "tests/test_framework.py",
    "studies.Study",
    "studies.new_figure",
)
exempt(
    "cache control without arguments (no input to validate)",
    "optimal_control.clear_cache",
    "studies.study_names",
    "cli.build_parser",
)
exempt(
    "needs a live Dask scheduler (optional dependency); its arguments are validated by the "
    "same helpers as ProcessExecutor",
    "uncertainty.DaskExecutor",
)

# ============================================================================================
# attitude
# ============================================================================================

Q = [0.1, -0.2, 0.3, 0.9273618495495703]  # unit quaternion, scalar last
Q2 = [0.0, 0.0, 0.0, 1.0]
DCM = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
SIGMA = [0.1, 0.2, -0.1]
W = [0.01, -0.02, 0.03]

for _n in ("quat_canonical", "quat_from_scalar_first", "quat_inverse", "quat_normalize",
           "quat_to_dcm", "quat_to_mrp", "quat_to_scalar_first", "to_scipy", "xi_matrix"):
    case(f"attitude.{_n}", exact=_n != "to_scipy")(lambda: dict(q=list(Q)))

for _n in ("dcm_to_mrp", "dcm_to_quat"):
    case(f"attitude.{_n}")(lambda: dict(A=[list(r) for r in DCM]))

case("attitude.dcm_to_euler")(lambda: dict(A=[list(r) for r in DCM], seq="321"))
case("attitude.euler_to_dcm")(lambda: dict(angles=[0.1, 0.2, 0.3], seq="313"))
case("attitude.error_angle")(lambda: dict(q1=list(Q), q2=list(Q2)))
case("attitude.quat_kinematics")(lambda: dict(q=list(Q), omega=list(W)))
case("attitude.quat_multiply")(lambda: dict(p=list(Q), q=list(Q2)))
case("attitude.random_quat")(lambda: dict(n=3, rng=1))
case("attitude.skew")(lambda: dict(v=[1.0, 2.0, 3.0]))
for _n in ("mrp_b_matrix", "mrp_shadow", "mrp_to_dcm", "mrp_to_quat"):
    case(f"attitude.{_n}")(lambda: dict(sigma=list(SIGMA)))
case("attitude.mrp_kinematics")(lambda: dict(sigma=list(SIGMA), omega=list(W)))
case("attitude.mrp_switch")(lambda: dict(sigma=[0.9, 0.5, 0.1], threshold=1.0))


@case("attitude.from_scipy", kinds={"rotation": "object"})
def _():
    from scipy.spatial.transform import Rotation

    return dict(rotation=Rotation.from_quat(Q))


# ============================================================================================
# dynamics
# ============================================================================================

J = [[10.0, 0.1, 0.0], [0.1, 8.0, 0.0], [0.0, 0.0, 6.0]]
JD = [[10.0, 0.0, 0.0], [0.0, 8.0, 0.0], [0.0, 0.0, 6.0]]

case("dynamics.as_inertia")(lambda: dict(inertia=[list(r) for r in J]))
case("dynamics.cw_matrices", positive=("n",))(lambda: dict(n=1.1e-3))
case("dynamics.cw_stm", positive=("n",))(lambda: dict(n=1.1e-3, t=100.0))
case("dynamics.discretize", positive=("dt",))(
    lambda: dict(A=[[0.0, 1.0], [0.0, 0.0]], B=[[0.0], [1.0]], dt=0.1, method="zoh")
)
case("dynamics.euler_equations")(lambda: dict(omega=list(W), inertia=[list(r) for r in J], torque=[0.1, 0.0, 0.0]))
case("dynamics.gravity_gradient_torque", positive=("mu",))(
    lambda: dict(r_body=[7.0e6, 1.0e5, 0.0], inertia=[list(r) for r in J], mu=3.986004418e14)
)
case("dynamics.lvlh_attitude_model", positive=("orbit_rate",))(
    lambda: dict(inertia=[list(r) for r in JD], orbit_rate=1.1e-3, printed=False)
)
case("dynamics.lvlh_second_order", positive=("orbit_rate",))(
    lambda: dict(inertia=[list(r) for r in JD], orbit_rate=1.1e-3, printed=False)
)
case("dynamics.orbit_rate", positive=("mu", "radius"))(lambda: dict(altitude=5e5, mu=3.986004418e14, radius=6378137.0))


def _torque(t: float, q: np.ndarray, w: np.ndarray) -> np.ndarray:
    return np.array([1e-3, 0.0, 0.0])


@case(
    "dynamics.propagate_attitude",
    positive=("rtol", "atol"),
    nan_ok=(),
    extra={
        "q0-1e299": ("q0", [0.0, 0.0, 1e299, 1e299], "finite"),
        "omega0-1e299": ("omega0", [1e299, 0.0, 0.0], "finite"),
        "torque-inf": ("torque", lambda t, q, w: np.array([np.inf, 0.0, 0.0]), "nonfinite"),
        "torque-shape": ("torque", lambda t, q, w: np.zeros(2), "type"),
        "torque-huge": ("torque", lambda t, q, w: np.array([1e300, 0.0, 0.0]), "finite"),
    },
)
def _():
    return dict(q0=list(Q), omega0=list(W), inertia=[list(r) for r in J], t_eval=[0.0, 1.0, 2.0],
                torque=_torque, method="DOP853", rtol=1e-8, atol=1e-10, max_nfev=20_000)


# ============================================================================================
# environment
# ============================================================================================

T0 = "2024-03-20T12:00:00"
TIMES = ["2024-03-20T12:00:00", "2024-03-21T00:00:00"]
R_ECI = [7.0e6, 1.0e5, 2.0e5]
TLE_00005 = (
    "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
    "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667",
)
TK = {"times": "times"}

case("environment.as_utc", kinds=TK)(lambda: dict(times=T0))
for _n in ("decimal_year", "dipole_coefficients", "eci_to_ecef_matrix", "gmst", "julian_centuries",
           "julian_date", "sun_direction", "sun_position"):
    case(f"environment.{_n}", kinds=TK)(lambda: dict(times=list(TIMES)))
case("environment.utc_times", kinds={"epoch": "times"})(lambda: dict(epoch=T0, t=[0.0, 60.0, 1e4]))
case("environment.ecef_to_eci", kinds=TK)(lambda: dict(r_ecef=list(R_ECI), times=T0))
case("environment.eci_to_ecef", kinds=TK)(lambda: dict(r_eci=list(R_ECI), times=T0))
case("environment.ecef_to_eci_state", kinds=TK)(lambda: dict(r_ecef=list(R_ECI), v_ecef=[0.0, 7.5e3, 0.0], times=T0))
case("environment.eci_to_ecef_state", kinds=TK)(lambda: dict(r_eci=list(R_ECI), v_eci=[0.0, 7.5e3, 0.0], times=T0))
case("environment.ecef_to_geocentric")(lambda: dict(r_ecef=list(R_ECI)))
case("environment.ecef_to_geodetic")(lambda: dict(r_ecef=list(R_ECI)))
case("environment.enu_to_ecef_matrix")(lambda: dict(lat=0.5, lon=1.0))
case("environment.ned_to_ecef_matrix")(lambda: dict(lat=0.5, lon=1.0))
case("environment.geocentric_to_ecef", positive=("radius",))(lambda: dict(radius=7.0e6, colat=1.0, lon=0.5))
case("environment.geodetic_to_ecef")(lambda: dict(lat=0.5, lon=1.0, h=5e5))
case("environment.in_shadow", kinds=TK, positive=("radius",))(lambda: dict(r_eci=list(R_ECI), times=T0, radius=6378137.0))
case("environment.magnetic_field", kinds=TK)(lambda: dict(r_eci=list(R_ECI), times=T0, model="dipole"))
case("environment.solve_kepler")(lambda: dict(mean_anomaly=[0.1, 1.0, 3.0], e=0.1))
case("environment.rv_to_elements", positive=("mu",))(lambda: dict(r=list(R_ECI), v=[0.0, 7.5e3, 100.0], mu=3.986004418e14))
case("environment.elements_to_rv", positive=("a", "mu"))(
    lambda: dict(a=7.0e6, e=0.01, inclination=0.9, raan=0.1, argp=0.2, true_anomaly=[0.0, 1.0], mu=3.986004418e14)
)
case("environment.circular_orbit", kinds={"epoch": "times"}, positive=("mu", "radius"))(
    lambda: dict(altitude=5e5, inclination=0.9, raan=0.1, arg_lat0=0.0, t=[0.0, 60.0], epoch=T0,
                 mu=3.986004418e14, radius=6378137.0)
)
case("environment.kepler_orbit", kinds={"epoch": "times"}, positive=("a", "mu"))(
    lambda: dict(a=7.0e6, e=0.01, inclination=0.9, raan=0.1, argp=0.2, mean_anomaly0=0.0,
                 t=[0.0, 60.0], epoch=T0, mu=3.986004418e14)
)
case("environment.KeplerOrbit", kinds={"epoch": "times"}, positive=("a", "mu"))(
    lambda: dict(a=7.0e6, e=0.01, inclination=0.9, raan=0.1, argp=0.2, mean_anomaly0=0.0, epoch=T0,
                 mu=3.986004418e14)
)


def _kepler() -> Any:
    from adcskit.environment import KeplerOrbit

    return KeplerOrbit(a=7.0e6, e=0.01, epoch=T0)


case("environment.KeplerOrbit.propagate", target=method("environment.KeplerOrbit", _kepler, "propagate"),
     extra={"t-1e300": ("t", [0.0, 1e300], "finite")})(lambda: dict(t=[0.0, 60.0, 600.0]))
case("environment.sgp4_orbit", kinds={"times": "times", "tle_line1": "choice", "tle_line2": "choice"})(
    lambda: dict(tle_line1=TLE_00005[0], tle_line2=TLE_00005[1], times="2000-06-28")
)

# ============================================================================================
# sensors
# ============================================================================================

A_ATT = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]
R_REF = [0.6, 0.0, 0.8]
SENSOR_KW = dict(noise_std=0.01, angle_bound=0.02, component_fraction=0.01, bias=[0.0, 0.001, 0.0],
                 misalignment=[0.001, -0.002, 0.0], normalize=True)

for _cls in ("VectorSensor", "SunSensor", "Magnetometer"):
    case(f"sensors.{_cls}", positive=("noise_std", "angle_bound", "component_fraction"))(lambda: dict(SENSOR_KW))


def _sensor() -> Any:
    from adcskit.sensors import VectorSensor

    return VectorSensor(**SENSOR_KW)


case("sensors.VectorSensor.measure", target=method("", _sensor, "measure"),
     degenerate={"zero-attitude": {"A": np.zeros((3, 3))}, "zero-ref": {"r": [0.0, 0.0, 0.0]},
                 "non-orthogonal": {"A": [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]]}})(
    lambda: dict(A=[list(r) for r in A_ATT], r=list(R_REF), rng=3)
)
case("sensors.VectorSensor.true_body", target=method("", _sensor, "true_body"),
     degenerate={"zero-attitude": {"A": np.zeros((3, 3))}, "zero-ref": {"r": [0.0, 0.0, 0.0]}})(
    lambda: dict(A=[list(r) for r in A_ATT], r=list(R_REF))
)
case("sensors.VectorSensor.interval", target=method("", _sensor, "interval"))(lambda: dict(measured=[0.6, 0.0, 0.8]))
case("sensors.interval_from_bounds")(lambda: dict(lower=[0.0, 0.1, 0.2], upper=[0.1, 0.3, 0.4]))
case("sensors.midpoint_radius", positive=("angle_bound", "fraction"))(
    lambda: dict(measured=[0.6, 0.0, 0.8], angle_bound=0.01, fraction=0.01, normalized=False)
)
case("sensors.vector_bounds", positive=("angle_bound", "fraction"))(
    lambda: dict(measured=[0.6, 0.0, 0.8], angle_bound=0.01, fraction=0.01, normalized=False)
)

GYRO_KW = dict(sigma_v=1e-5, sigma_u=1e-7, rate_hz=10.0, bias0=[1e-4, 0.0, -2e-4])
case("sensors.RateGyro", positive=("sigma_v", "sigma_u", "rate_hz"))(lambda: dict(GYRO_KW))


def _gyro() -> Any:
    from adcskit.sensors import RateGyro

    return RateGyro(**GYRO_KW)


case("sensors.RateGyro.measure", target=method("", _gyro, "measure"))(
    lambda: dict(omega=np.full((6, 3), 0.01), rng=4, t0=10.0)
)

# ============================================================================================
# determination
# ============================================================================================

BODY = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
REF = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
COLLINEAR = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]

case("determination.davenport_k", positive=("weights",),
     degenerate={})(lambda: dict(body=[list(r) for r in BODY], ref=[list(r) for r in REF], weights=[1.0, 2.0, 3.0]))
case("determination.wahba_loss", positive=("weights",))(
    lambda: dict(q=list(Q), body=[list(r) for r in BODY], ref=[list(r) for r in REF], weights=[1.0, 2.0, 3.0])
)
case("determination.solve_wahba", positive=("weights",),
     degenerate={"collinear": {"body": COLLINEAR, "ref": COLLINEAR}})(
    lambda: dict(body=[list(r) for r in BODY], ref=[list(r) for r in REF], weights=[1.0, 2.0, 3.0],
                 method="q-method", covariance=True)
)
_RB = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
_RR = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]


@case(
    "determination.robust_wahba",
    positive=("body_radius", "ref_radius", "weights", "search_range"),
    degenerate={
        "collinear-q0": {"body_mid": COLLINEAR, "ref_mid": COLLINEAR, "q0": [0.0, 0.0, 0.0, 1.0]},
        "collinear": {"body_mid": COLLINEAR, "ref_mid": COLLINEAR},
    },
    kinds={"delta": "skip"},
)
def _():
    return dict(body_mid=[list(r) for r in _RB], body_radius=[[0.02] * 3] * 3, ref_mid=[list(r) for r in _RR],
                ref_radius=[[0.02] * 3] * 3, weights=[1.0, 1.0, 1.0], method="minmax", search_range=0.1,
                q0=[0.0, 0.0, 0.7071067811865476, 0.7071067811865476], solver="closed-form", maxiter=50, rng=0)


case("determination.interval_objectives", positive=("body_radius", "ref_radius", "weights"))(
    lambda: dict(q=list(Q), alpha=np.full((3, 3), 0.5), beta=np.full((3, 3), 0.5), body_mid=[list(r) for r in _RB],
                 body_radius=[[0.02] * 3] * 3, ref_mid=[list(r) for r in _RR], ref_radius=[[0.02] * 3] * 3,
                 weights=[1.0, 1.0, 1.0])
)

# ============================================================================================
# estimation
# ============================================================================================

A2 = [[0.9, 0.1], [0.0, 0.8]]
B2 = [[0.0], [1.0]]
C2 = [[1.0, 0.0], [0.0, 1.0]]


def _sim(n: int = 30) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    u = rng.normal(size=(n, 1))
    x = np.zeros((n + 1, 2))
    for k in range(n):
        x[k + 1] = np.array(A2) @ x[k] + np.array(B2) @ u[k] + 0.01 * rng.normal(size=2)
    return x, u


case("estimation.simulate_linear", positive=("R", "Q"))(
    lambda: dict(A=A2, B=B2, C=C2, u=_sim()[1], x0=[0.1, 0.0], R=0.01, Q=0.001, rng=1)
)
case("estimation.kalman_filter", positive=("R", "Q", "P0"))(
    lambda: dict(A=A2, B=B2, C=C2, y=_sim()[0][1:], u=_sim()[1], Q=0.001, R=0.01, x0=[0.0, 0.0], P0=1.0,
                 form="predict-update")
)
case("estimation.KalmanFilter")(  # P0 is a matrix: off-diagonal entries may be negative
    lambda: dict(x0=[0.0, 0.0], P0=[[1.0, 0.0], [0.0, 1.0]], form="predict-update"))
case("estimation.RecursiveLeastSquares", positive=("delta",))(lambda: dict(Theta0=np.zeros((3, 2)), delta=100.0, forgetting=0.99))


def _rls() -> Any:
    from adcskit.estimation import RecursiveLeastSquares

    return RecursiveLeastSquares(np.zeros((3, 2)), delta=100.0, forgetting=0.99)


case("estimation.RecursiveLeastSquares.update", target=method("", _rls, "update"))(
    lambda: dict(phi=[0.1, 0.2], z=[0.3, 0.1, 0.2], validate=True)
)


def _kf_step() -> Callable[..., Any]:
    """``KalmanFilter.step`` on a fresh filter per call (a step advances the filter's state)."""
    from adcskit.estimation import KalmanFilter

    def step(y, u, A, B, C, Q, R, *, validate=True):
        return KalmanFilter([0.0, 0.0], 1.0).step(y, u, A, B, C, Q, R, validate=validate)

    return step


case("estimation.KalmanFilter.step", target=_kf_step, positive=("R", "Q"))(
    lambda: dict(y=[0.5, 0.1], u=[0.0], A=A2, B=B2, C=C2, Q=0.001, R=0.01, validate=True)
)
case("estimation.RecursiveLeastSquares.update_batch", target=method("", _rls, "update_batch"))(
    lambda: dict(Phi=np.arange(8.0).reshape(4, 2) / 10, Z=np.arange(12.0).reshape(4, 3) / 10)
)
case("estimation.regression_data")(
    lambda: dict(states=_sim()[0][:-1], targets=_sim()[0][1:], inputs=_sim()[1], B=B2, estimate_B=False)
)
case("estimation.identify_model", nan_ok=("reg_param",),
     degenerate={"zero-data-gmres": {"states": np.zeros((30, 2)), "targets": np.zeros((30, 2)), "method": "gmres"},
                 "zero-data-qr": {"states": np.zeros((30, 2)), "targets": np.zeros((30, 2))}},
     extra={"options-bad-type": ("options", {"rtol": "abc"}, "type")})(
    lambda: dict(states=_sim()[0][:-1], targets=_sim()[0][1:], inputs=_sim()[1], B=B2, estimate_B=False,
                 method="qr", rng=0)
)
case("estimation.offline_schedule")(lambda: dict(n_states=3))


def _model(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.array([[0.9, p[0]], [0.0, 0.8]]), np.array([[0.0], [1.0]])


case("estimation.augmented_ekf", positive=("P_p0", "Q_p", "Q", "R", "P0", "p_min", "fd_step"),
     nan_ok=())(
    lambda: dict(y=_sim()[0][1:], u=_sim()[1], model=_model, p0=[0.05], P_p0=1.0, Q_p=1e-6, C=C2, Q=0.001,
                 R=0.01, x0=[0.0, 0.0], P0=1.0, p_min=0.05, fd_step=1e-6)
)
case("estimation.joint_estimate", positive=("Q", "R", "P0"), slow=True)(
    lambda: dict(y=_sim()[0][1:], u=_sim()[1], A_prior=A2, B=B2, C=C2, Q=0.001, R=0.01, x0=[0.0, 0.0],
                 P0=1.0, method="adaptive-gmres-online", estimate_B=False, start=10, passes=1,
                 form="predict-update", rng=0)
)

MEKF_P0 = np.diag([1e-2] * 3 + [1e-8] * 3)
MEKF_KW = dict(q0=[0.0, 0.0, 0.0, 1.0], b0=[0.0, 0.0, 0.0], P0=MEKF_P0, sigma_v=1e-5, sigma_u=1e-8)
case("estimation.MultiplicativeEKF", positive=("sigma_v", "sigma_u"))(lambda: dict(MEKF_KW, P0=MEKF_P0.copy()))


def _mekf_step(meth: str) -> Callable[[], Callable[..., Any]]:
    """A fresh filter's method; returns the method's value and the filter's state after it
    (``propagate`` returns None, so a NaN it wrote into the state would go unseen)."""

    def target() -> Callable[..., Any]:
        from adcskit.estimation import MultiplicativeEKF

        def call(**kw: Any) -> Any:
            f = MultiplicativeEKF(**dict(MEKF_KW, P0=MEKF_P0.copy()))  # fresh state every call
            out = getattr(f, meth)(**kw)
            return {"value": out, "q": f.q, "b": f.b, "P": f.P}

        return call

    return target


case("estimation.MultiplicativeEKF.propagate", target=_mekf_step("propagate"), positive=("dt",))(
    lambda: dict(omega_meas=[0.01, -0.02, 0.005], dt=0.5)
)
case("estimation.MultiplicativeEKF.update_vector", target=_mekf_step("update_vector"), positive=("sigma",),
     degenerate={"zero-body": {"v_body": [0.0, 0.0, 0.0]}, "zero-ref": {"v_ref": [0.0, 0.0, 0.0]}})(
    lambda: dict(v_body=[0.99, 0.1, 0.0], v_ref=[1.0, 0.0, 0.0], sigma=1e-3)
)
case("estimation.MultiplicativeEKF.update_quaternion", target=_mekf_step("update_quaternion"), positive=("sigma",),
     degenerate={"zero-q": {"q_meas": [0.0, 0.0, 0.0, 0.0]}})(
    lambda: dict(q_meas=[0.001, 0.0, 0.0, 1.0], sigma=1e-3)
)
case("estimation.MultiplicativeEKF.nees", target=_mekf_step("nees"))(
    lambda: dict(q_true=[0.001, 0.0, 0.0, 1.0], b_true=[1e-5, 0.0, 0.0])
)
case("estimation.chi2_band", positive=("alpha",))(lambda: dict(dof=6, n_runs=20, alpha=0.05))


def _mekf_data(T: int = 5) -> dict[str, Any]:
    rng = np.random.default_rng(5)
    t = np.arange(T, dtype=float)
    ref = np.broadcast_to(np.eye(3)[:2], (T, 2, 3)).copy()
    body = ref + 1e-3 * rng.standard_normal((T, 2, 3))
    gyro = 1e-4 + 1e-5 * rng.standard_normal((T, 3))
    q_true = np.tile([0.0, 0.0, 0.0, 1.0], (T, 1))
    q_star = q_true + np.array([1e-3, 0.0, 0.0, 0.0])
    return dict(q0=[0.0, 0.0, 0.0, 1.0], b0=np.zeros(3), P0=np.diag([1e-2] * 3 + [1e-6] * 3), t=t, gyro=gyro,
                vectors_body=body, vectors_ref=ref, sigmas=[1e-3, 1e-3], sigma_v=1e-5, sigma_u=1e-7,
                q_star=q_star, sigma_star=1e-3, q_true=q_true, b_true=np.full((T, 3), 1e-4),
                full_covariance=True)


def _warmed(name: str, make_kw: Callable[[], dict[str, Any]]) -> Callable[[], Callable[..., Any]]:
    """``target=`` for a numba-compiled entry point: one untimed call first, so that a cold JIT
    cache (minutes of compilation on a loaded machine) is not mistaken for a hang."""

    def target() -> Callable[..., Any]:
        import importlib

        mod, attr = name.rsplit(".", 1)
        fn = getattr(importlib.import_module("adcskit." + mod), attr)
        if name not in _WARM:
            fn(**make_kw())
            _WARM.add(name)
        return fn

    return target


_WARM: set[str] = set()


# NEES is documented NaN while P is singular (a singular P0, e.g. a known bias, at the first epochs)
case("estimation.mekf_filter", target=_warmed("estimation.mekf_filter", _mekf_data), positive=("sigma_v", "sigma_u", "sigma_star", "sigmas"), nan_ok=("nees", "mean_nees"),
     degenerate={"zero-body": {"vectors_body": np.zeros((5, 2, 3))}})(_mekf_data)

# ============================================================================================
# optimal_control
# ============================================================================================


def _di() -> Any:
    from adcskit.optimal_control.problems import double_integrator_min_energy

    return double_integrator_min_energy(1.0, 1.0)


_SOL: dict[str, Any] = {}


def _solution() -> Any:
    if "s" not in _SOL:
        from adcskit.optimal_control import solve

        _SOL["s"] = solve(_di(), method="gauss", mesh=(3, 3))
    return _SOL["s"]


#: Infinite bounds of a problem are legitimate (unbounded states); so are the scales derived.
OCP_NAN = ("state_lower", "state_upper", "control_lower", "control_upper", "state_scale", "control_scale",
           "tf_bounds", "problem")

IPOPT_EXTRA = {
    "ipopt-unknown": ("ipopt_options", {"no_such_ipopt_option": 1}, "type"),
    "ipopt-ill-typed": ("ipopt_options", {"max_iter": "many"}, "type"),
    "ipopt-none-value": ("ipopt_options", {"tol": None}, "type"),
}

for _n in ("legendre_gauss", "legendre_gauss_radau", "gauss_differentiation_matrix", "radau_differentiation_matrix"):
    case(f"optimal_control.{_n}")(lambda: dict(n=4))
case("optimal_control.lagrange_matrix")(lambda: dict(support=[-1.0, 0.0, 1.0], points=[-0.5, 0.5]))
case("optimal_control.lagrange_derivative_matrix")(lambda: dict(support=[-1.0, 0.0, 1.0], points=[-0.5, 0.5]))
case("optimal_control.Mesh")(lambda: dict(nodes=(3, 4), fractions=(0.5, 0.5)))
case("optimal_control.Guess", positive=("tf",))(
    lambda: dict(t=[0.0, 0.5, 1.0], x=[[0.0, 0.0], [0.5, 1.0], [1.0, 0.0]], u=[[1.0], [0.0], [-1.0]], tf=1.0)
)
case("optimal_control.OptimalControlProblem", kinds={"name": "skip"},
     nan_ok=(*OCP_NAN, "initial_state", "final_state"),
     nonfinite_ok=("initial_state", "final_state", "control_lower", "control_upper", "dynamics", "lagrange",
                   "tf_bounds"))(
    lambda: dict(dynamics=lambda x, u, t: [x[1], u[0]], n_states=2, n_controls=1,
                 initial_state=[0.0, 0.0], final_state=[1.0, 0.0], control_lower=[-10.0], control_upper=[10.0],
                 tf_bounds=(1.0, 1.0), lagrange=lambda x, u, t: u[0] ** 2)
)
case("optimal_control.default_guess", kinds={"problem": "object"})(lambda: dict(problem=_di()))
case("optimal_control.random_guess", kinds={"problem": "object"}, positive=("spread",))(
    lambda: dict(problem=_di(), rng=2, spread=0.5, knots=4)
)
case("optimal_control.solve", nan_ok=OCP_NAN, kinds={"problem": "object"}, extra=IPOPT_EXTRA)(
    lambda: dict(problem=_di(), method="gauss", mesh=(3, 3), ipopt_options={"max_iter": 200})
)
# tf_change is NaN for the first mesh without a guess solution (documented); branch_jumps has
# one index per flagged solve, so its length depends on rtol
case("optimal_control.solve_mesh_sequence", nan_ok=(*OCP_NAN, "rel_change", "tf_change"), shape_stable=False, aliases={"meshes": ("mesh",)}, kinds={"problem": "object"}, positive=("rtol",), extra=IPOPT_EXTRA,
     slow=True)(
    lambda: dict(problem=_di(), meshes=((3, 3), (4, 3)), method="gauss", rtol=1e-5, ipopt_options={"max_iter": 200})
)
case("optimal_control.multistart", nan_ok=OCP_NAN, shape_stable=False, kinds={"problem": "object"}, positive=("spread", "rtol"), extra=IPOPT_EXTRA,
     slow=True)(
    lambda: dict(problem=_di(), n_starts=2, method="gauss", mesh=(3, 3), rng=1, include_default=True, spread=0.5,
                 rtol=1e-4, ipopt_options={"max_iter": 200})
)
case("optimal_control.resimulate", kinds={"solution": "object"}, positive=("rtol", "atol"))(
    lambda: dict(solution=_solution(), control="lagrange", method="DOP853", rtol=1e-8, atol=1e-10,
                 points_per_interval=3)
)
case("optimal_control.bang_bang", kinds={"solution": "object"}, positive=("tol", "min_fraction"))(
    lambda: dict(solution=_solution(), tol=0.02, min_fraction=0.9)
)
case("optimal_control.problems.double_integrator_min_energy", nan_ok=OCP_NAN, positive=("distance", "duration"))(
    lambda: dict(distance=1.0, duration=1.0)
)
case("optimal_control.problems.double_integrator_min_time", nan_ok=OCP_NAN, positive=("distance", "accel_max"))(
    lambda: dict(distance=1.0, accel_max=1.0)
)
case("optimal_control.problems.RendezvousParams", positive=("inertia", "mass", "torque_max", "force_max", "altitude"))(
    lambda: dict(inertia=(5621.0, 4547.0, 2364.0), mass=3200.0, torque_max=(50.0, 50.0, 50.0),
                 force_max=(320.0, 320.0, 320.0), altitude=580000.0)
)
case("optimal_control.problems.rendezvous_problem", nan_ok=OCP_NAN, positive=("tf_guess",), kinds={"params": "skip"})(
    lambda: dict(s0=(20.0, 0.0, 0.0), sf=(0.0, 0.0, -10.0), sigma_f=(0.0, 0.41421356237309503, 0.0),
                 dynamics="paper", tf_guess=25.0)
)

# ============================================================================================
# thrusters
# ============================================================================================

POS = [[1.0, 0.5, 0.0], [-1.0, 0.5, 0.0], [1.0, -0.5, 0.0], [-1.0, -0.5, 0.0], [0.0, 0.5, 1.0], [0.0, -0.5, -1.0]]
DIRS = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]


def _tm() -> np.ndarray:
    from adcskit.thrusters import torque_matrix

    return torque_matrix(POS, DIRS)


CUBE = np.array([[1, 1, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1], [0.5, 0, 0]], dtype=float)


def _cube_tm() -> np.ndarray:
    # 8 thrusters on a cube's corners, tangential directions: a controllable set.
    from adcskit.thrusters import torque_matrix

    pos, dirs = [], []
    for sx in (1.0, -1.0):
        for sy in (1.0, -1.0):
            pos += [[sx, sy, 1.0], [sx, sy, -1.0]]
            dirs += [[-sy, sx, 0.0], [sy, -sx, 0.0]]
    d = np.array(dirs) / np.sqrt(2)
    d[::2, 2] = 0.3
    d[1::2, 2] = -0.3
    return torque_matrix(np.array(pos), d / np.linalg.norm(d, axis=1, keepdims=True))


case("thrusters.torque_matrix")(lambda: dict(positions=POS, directions=DIRS))
case("thrusters.angles_from_direction")(lambda: dict(direction=[0.0, 0.6, 0.8]))
case("thrusters.direction_from_angles")(lambda: dict(alpha=0.3, beta=0.2))
case("thrusters.check_controllability", positive=("tol",))(lambda: dict(torque_matrix=_cube_tm(), tol=1e-9))
case("thrusters.allocate", positive=("f_max",),
     degenerate={"zero-f_max": {"f_max": 0.0}},
     extra={"demand-1e299": ("demand", [1e299, 0.0, 0.0], "finite"),
            "f_max-negative": ("f_max", -1.0, "negative")})(
    lambda: dict(torque_matrix=_cube_tm(), demand=[0.5, -0.2, 0.1], method="lp-min-fuel", f_max=10.0)
)
case("thrusters.Thruster", positive=("f_max", "t_min", "mdot"))(
    lambda: dict(position=[1.0, 0.0, 0.0], direction=[0.0, 1.0, 0.0], f_max=10.0, t_min=0.003, mdot=0.0035)
)
case("thrusters.Thruster.from_angles", positive=("f_max",))(
    lambda: dict(position=[1.0, 0.0, 0.0], alpha=0.3, beta=0.2, f_max=10.0)
)
case("thrusters.ThrusterSet", positive=("f_max", "t_min", "mdot"), kinds={"names": "skip"})(
    lambda: dict(positions=POS, directions=DIRS, f_max=10.0, t_min=0.003, mdot=0.0035, com=(0.0, 0.0, 0.0))
)
case("thrusters.MountingFace", positive=("half_u", "half_v", "max_cant"), kinds={"name": "skip"})(
    lambda: dict(name="+X", centre=[1.0, 0.0, 0.0], normal=[1.0, 0.0, 0.0], axis_u=[0.0, 1.0, 0.0],
                 axis_v=[0.0, 0.0, 1.0], half_u=1.0, half_v=1.0, max_cant=1.0)
)
case("thrusters.box_faces", positive=("half_size", "max_cant"), kinds={"names": "skip"})(
    lambda: dict(half_size=(1.0, 1.0, 1.0), max_cant=1.0)
)


def _faces() -> Any:
    from adcskit.thrusters import box_faces

    return box_faces()


case("thrusters.decode_layout", kinds={"faces": "object"})(
    lambda: dict(genes=np.tile([0.1, 0.2, 0.3, 0.4, 0.5], 2), faces=_faces(), com=(0.0, 0.0, 0.0))
)
DEMANDS = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
case("thrusters.score_layout", positive=("f_max", "t_min", "t_s", "gain"))(
    lambda: dict(torque_matrix=_cube_tm(), demands=DEMANDS, weights=(100.0, -99.0, 12.0), f_max=10.0, t_min=0.003,
                 t_s=0.2, gain=600.0)
)
case("thrusters.design_layout", positive=("f_max", "t_min", "mdot", "t_s", "gain"), kinds={"mounting": "skip"},
     slow=True)(
    lambda: dict(n_thrusters=8, demands=DEMANDS, algorithm="de", f_max=10.0, t_min=0.003, mdot=0.0035, t_s=0.2,
                 gain=600.0, pop_size=4, n_gen=1, de_strategy="current-to-best/1/bin", de_F=0.8, de_CR=0.9, rng=0)
)
case("thrusters.fuel_mass", positive=("t_p", "mdot"))(lambda: dict(t_p=[0.01, 0.02, 0.0], mdot=0.0035))
case("thrusters.manoeuvre_fuel", positive=("f_max", "t_s", "mdot", "t_min"))(
    lambda: dict(forces=[[1.0, 2.0, 0.0], [0.5, 0.0, 3.0]], f_max=10.0, t_s=0.2, mdot=0.0035, t_min=0.003)
)
case("thrusters.min_impulse_bit", positive=("f_max", "t_min"))(lambda: dict(lever_arm=[1.0, 0.5], f_max=10.0, t_min=0.003))
case("thrusters.min_reachable_error", positive=("f_max", "t_min", "t_s", "gain"))(
    lambda: dict(lever_arm=[1.0, 0.5], f_max=10.0, t_min=0.003, t_s=0.2, gain=600.0)
)
case("thrusters.pulse_width", positive=("force", "f_max", "t_s"))(lambda: dict(force=[1.0, 5.0, 0.0], f_max=10.0, t_s=0.2))
case("thrusters.realisable_pulses", positive=("t_p", "t_min"))(lambda: dict(t_p=[0.001, 0.01, 0.1], t_min=0.003, mode="drop"))
case("thrusters.s3_manoeuvre_demands", positive=("correction_deg", "gain"))(lambda: dict(correction_deg=0.5, gain=600.0))

# ============================================================================================
# control
# ============================================================================================

LOOP = dict(kp=56.24, ki=0.02, kd=49.99, u_on=0.15, off_ratio=0.5, inertia=10.0, torque=1.0, delay=0.02,
            disturbance=0.05, disturbance_amp=0.0, disturbance_freq_hz=0.0, theta_ref=0.26, theta0=0.0, omega0=0.0)
SETTINGS = dict(dt=0.001, t_final=0.2, t_window=0.1, tau_thruster=0.01, tau_deriv=0.01, command_rate_hz=50.0,
                settle_band=0.02)

case("control.LoopParams", positive=("inertia", "torque", "delay", "u_on"))(lambda: dict(LOOP))
case("control.LoopSettings", positive=tuple(SETTINGS))(lambda: dict(SETTINGS))


def _params() -> Any:
    from adcskit.control import LoopParams

    return LoopParams(**LOOP)


def _settings() -> Any:
    from adcskit.control import LoopSettings

    return LoopSettings(**SETTINGS)


case("control.simulate_batch", kinds={"params": "object", "settings": "object"}, nan_ok=("settling_time",))(
    lambda: dict(params=_params(), settings=_settings(), backend="numba", parallel=False)
)
case("control.simulate_trace", kinds={"params": "object", "settings": "object"}, nan_ok=("settling_time",))(
    lambda: dict(params=_params(), settings=_settings(), backend="numba")
)
case("control.schmitt_trigger")(lambda: dict(u=[0.0, 0.2, 0.1, 0.05, -0.2], u_on=0.15, u_off=0.07, state=0.0))
case("control.fuel_to_propellant", positive=("fuel", "lever_arm", "isp", "mass"))(
    lambda: dict(fuel=[1.0, 2.0], lever_arm=0.5, isp=220.0, mass=100.0)
)

# ============================================================================================
# uncertainty
# ============================================================================================

case("uncertainty.Gaussian", positive=("std",))(lambda: dict(mean=1.0, std=0.1))
case("uncertainty.TruncatedGaussian", positive=("std",), nonfinite_ok=("low", "high"), nan_ok=("low", "high"))(
    lambda: dict(mean=1.0, std=0.1, low=0.8, high=1.3)
)
case("uncertainty.Fixed")(lambda: dict(value=1.0))
for _c in ("Gaussian", "TruncatedGaussian", "Fixed"):
    def _make(c: str = _c) -> Any:
        import adcskit.uncertainty as u

        kw = {"Fixed": dict(value=1.0)}.get(c, dict(mean=1.0, std=0.1))
        return getattr(u, c)(**kw)

    case(f"uncertainty.{_c}.ppf", target=method("", _make, "ppf"))(lambda: dict(u=[0.1, 0.5, 0.9]))


@case("uncertainty.latin_hypercube", kinds={"dists": "mapping"})
def _():
    from adcskit.uncertainty import Fixed, Gaussian

    return dict(dists={"a": Gaussian(mean=1.0, std=0.1), "b": Fixed(value=2.0)}, n=5, rng=1)


case("uncertainty.sample_stats", nonfinite_ok=("x",))(lambda: dict(x=[1.0, 2.0, 3.0, 4.0]))
case("control.mean_change_converged", positive=("tol",))(lambda: dict(history=[1.0, 1.1, 1.05, 1.04], tol=1e-3, window=2))
case("control.robust_objective", nonfinite_ok=("errors", "overshoot_pct"), positive=("w1", "w2", "overshoot_max_pct", "penalty_weight"))(
    lambda: dict(errors=[[0.1, 0.2], [0.3, 0.1]], overshoot_pct=[[1.0, 2.0], [3.0, 20.0]], w1=1.0, w2=1.0,
                 overshoot_max_pct=10.0, penalty_weight=1.0)
)
case("control.weights_from_ratio", positive=("ratio",))(lambda: dict(ratio=2.0))
case("uncertainty.make_executor", kinds={"spec": "choice"}, aliases={"spec": ("executor",)})(lambda: dict(spec="serial"))
case("uncertainty.SerialExecutor")(lambda: dict())
case("uncertainty.ProcessExecutor")(lambda: dict(n_workers=1))


def _square(x: float) -> float:
    return x * x


@case("uncertainty.run_campaign", kinds={"directory": "path", "description": "skip", "executor": "skip", "tasks": "object"},
      nan_ok=("values",), nonfinite_ok=("fn",))
def _():
    return dict(fn=_square, tasks=[1.0, 2.0, 3.0], directory=scratch_path("campaign-"), chunk_size=2)


case("uncertainty.SerialExecutor.map", target=lambda: __import__("adcskit.uncertainty", fromlist=["x"]).SerialExecutor().map,
     kinds={"description": "skip", "tasks": "object"}, nan_ok=("*",), nonfinite_ok=("fn",))(lambda: dict(fn=_square, tasks=[1.0, 2.0]))

# ============================================================================================
# report, config, cli, studies
# ============================================================================================


def _results_dir() -> str:
    return scratch_path("report-")


case("report.load_results", kinds={"out": "path"})(lambda: dict(out=_results_dir()))
case("report.build_report", kinds={"out": "path", "title": "skip"})(lambda: dict(out=_results_dir()))


def _toml_file() -> str:
    path = scratch_path("config-", file_suffix=".toml")
    with open(path, "w") as f:
        f.write('a = 1\n[b]\nc = "x"\n')
    return path


case("config.read_toml", kinds={"path": "path"})(lambda: dict(path=_toml_file()))
case("config.dump_toml", kinds={"_prefix": "skip"}, open_keys=("data",))(lambda: dict(data={"a": 1, "b": {"c": 2.5}}))
case("config.merge_mappings", open_keys=("base", "override"))(lambda: dict(base={"a": 1, "b": {"c": 2}}, override={"b": {"c": 3}}))


def _cfg_cls() -> type:
    from adcskit.control import LoopSettings

    return LoopSettings


case("config.load_config", kinds={"cls": "skip"},
     aliases={"source": ("config", "path"), "overrides": ("config",)})(
    lambda: dict(cls=_cfg_cls(), source={"dt": 0.002}, overrides={"t_final": 20.0})
)
case("config.config_help", kinds={"cls": "object"})(lambda: dict(cls=_cfg_cls()))
case("config.config_to_dict", kinds={"config": "object"})(lambda: dict(config=_settings()))
case("cli.main", kinds={"argv": "skip"}, exit_ok=True,
     extra={"argv-unknown-command": ("argv", ["no-such-command"], "type"),
            "argv-out-unwritable": ("argv", ["report", "--out", "/proc/adcskit-no-such-dir"], "type"),
            "argv-none-item": ("argv", [None], "type"),
            "argv-string": ("argv", "list", "type")})(lambda: dict(argv=["list"]))
case("studies.get_study", aliases={"name": ("study",)})(lambda: dict(name="wahba-table1"))
case("studies.is_available", aliases={"name": ("study",)})(lambda: dict(name="wahba-table1"))
case("studies.resolve_config", kinds={"config": "skip"}, aliases={"name": ("study",)})(lambda: dict(name="wahba-table1", quick=True))


def _study_config_cls() -> Any:
    from adcskit.studies.wahba_table1.config import Config

    return Config


case("studies.neutral_keys")(lambda: dict(config_cls=_study_config_cls()))
case("studies.protocol_keys")(lambda: dict(config_cls=_study_config_cls()))
case("studies.paper_protocol")(lambda: dict(config_cls=_study_config_cls()))
exempt("takes only *tags (no keyword to mutate); its checks (non-empty strings, at least one) are tested in "
       "tests/test_framework.py::test_config_keys_are_declared_as_field_metadata", "studies.protocol")
exempt(
    "runs or writes a whole study (minutes); its argument checks are exercised end to end by "
    "tests/test_framework.py with the fake study",
    "studies.run_study",
    "studies.write_result",
)
exempt(
    "framework helpers of the CLI: write_json_atomic writes any JSON-able object (its path is "
    "checked by the CLI's --out validation), tally counts outcome strings (an unknown one is "
    "counted, by design)",
    "studies.write_json_atomic",
    "studies.tally",
)


# studies: the verdict model


def _ratio(m: Any) -> float:
    return float(m["ratio"])


SPEC_KW = dict(id="faster", statement="A is faster than B", where="Table 1", quantity="time ratio B/A",
               value=_ratio, threshold=1.0, better="above", stochastic=True)
RUNS = {"default": [{"ratio": r} for r in (3.1, 2.9, 3.4, 3.0, 3.2)]}
# NaN / inf values are a failed seed (decided as not supporting); "no seeds" gives NaN fraction_held
case("studies.decide", nonfinite_ok=("values",), nan_ok=("fraction_held",), kinds={"reading": "skip"})(
    lambda: dict(values=[1.2, 1.3, 1.1, 1.25, 1.15], threshold=1.0, better="above", stochastic=True,
                 confidence=0.95)
)
for _c in ("ClaimSpec", "FindingSpec"):
    # a value callable that returns NaN for a seed is legal (a failed seed); cannot be seen here
    case(f"studies.{_c}", kinds={"id": "skip", "statement": "skip", "where": "skip", "quantity": "skip"},
         nonfinite_ok=("value",))(
        lambda: dict(SPEC_KW)
    )


def _spec() -> Any:
    from adcskit.studies import ClaimSpec

    return ClaimSpec(**SPEC_KW)


case("studies.ClaimSpec.evaluate", target=method("", _spec, "evaluate"), kinds={"detail": "skip"},
     aliases={"default": ("readings",)})(
    lambda: dict(runs={k: [dict(m) for m in v] for k, v in RUNS.items()}, default="default")
)


# optimal_control: hp-adaptive and multi-phase (h15)
exempt(
    RESULT,
    "optimal_control.AdaptiveSolution",
    "optimal_control.ErrorCertificate",
    "optimal_control.MeshIteration",
    "optimal_control.MultiPhaseSolution",
)
exempt("symbolic (CasADi) endpoint the transcription passes to user objective/event functions; "
       "not an entry point", "optimal_control.Endpoint")


def _mp_dyn(x: Any, u: Any, t: Any, p: Any) -> Any:
    return [x[1], u[0]]


PHASE_NAN = (*OCP_NAN, "initial_state", "final_state", "t0_bounds", "duration_bounds", "path_lower",
             "path_upper", "integral_lower", "integral_upper")


def _phases() -> list[Any]:
    from adcskit.optimal_control import Phase

    acc = Phase(dynamics=_mp_dyn, n_states=2, n_controls=1, control_lower=[1.0], control_upper=[1.0],
                initial_state=[0.0, 0.0], tf_bounds=(0.0, 10.0))
    dec = Phase(dynamics=_mp_dyn, n_states=2, n_controls=1, control_lower=[-1.0], control_upper=[-1.0],
                final_state=[np.nan, 0.0], t0_bounds=(0.0, 10.0), tf_bounds=(0.0, 10.0))
    return [acc, dec]


def _mp_kw() -> dict[str, Any]:
    return dict(phases=_phases(), n_parameters=1, parameter_lower=[1.0], parameter_upper=[1.0],
                objective=lambda e, p: e[1].tf, events=lambda e, p: [e[1].xf[0] - p[0]], event_lower=[0.0],
                event_upper=[0.0])


def _mp() -> Any:
    from adcskit.optimal_control import MultiPhaseProblem

    return MultiPhaseProblem(**_mp_kw())


case("optimal_control.Phase", kinds={"name": "skip"}, nan_ok=PHASE_NAN,
     nonfinite_ok=("initial_state", "final_state", "control_lower", "control_upper", "tf_bounds", "dynamics"))(
    lambda: dict(dynamics=_mp_dyn, n_states=2, n_controls=1, control_lower=[-1.0], control_upper=[1.0],
                 initial_state=[0.0, 0.0], final_state=[1.0, 0.0], tf_bounds=(0.0, 10.0))
)
case("optimal_control.Link")(lambda: dict(a=0, b=1, jump=0.0, time=True))
# infinite parameter / event bounds are legal (unbounded), as for OptimalControlProblem
case("optimal_control.MultiPhaseProblem", kinds={"phases": "object"}, nan_ok=("*",),
     nonfinite_ok=("objective", "events", "parameter_lower", "parameter_upper", "event_lower", "event_upper"))(_mp_kw)


def _mp_guess_kw() -> dict[str, Any]:
    from adcskit.optimal_control import default_multiphase_guess

    g = default_multiphase_guess(_mp())
    return dict(phases=g.phases, parameters=[1.0])


case("optimal_control.MultiPhaseGuess", kinds={"phases": "object"})(_mp_guess_kw)
case("optimal_control.default_multiphase_guess", kinds={"problem": "object"})(lambda: dict(problem=_mp()))
case("optimal_control.solve_multiphase", kinds={"problem": "object", "meshes": "object"}, nan_ok=("*",),
     aliases={"meshes": ("mesh",)}, extra=IPOPT_EXTRA, slow=True)(
    lambda: dict(problem=_mp(), method="radau", meshes=[(1, 3), (1, 3)], ipopt_options={"max_iter": 100})
)
case("optimal_control.estimate_error", kinds={"solution": "object"})(
    lambda: dict(solution=_solution(), extra_points=1)
)


def _mesh24() -> Any:
    from adcskit.optimal_control import Mesh

    return Mesh.uniform(2, 4)


# the number of intervals of the new mesh depends on the errors
case("optimal_control.refine_mesh", kinds={"mesh": "object"}, positive=("tol",), shape_stable=False)(
    lambda: dict(mesh=_mesh24(), errors=[1e-3, 1e-9], tol=1e-6, n_min=3, n_max=10, smooth_decay=1.0,
                 jump_threshold=0.5)
)


def _di_min_time() -> Any:
    from adcskit.optimal_control.problems import double_integrator_min_time

    return double_integrator_min_time(1.0, 1.0)


case("optimal_control.solve_adaptive", kinds={"problem": "object"}, nan_ok=("*",), positive=("tol",),
     extra=IPOPT_EXTRA, slow=True)(
    lambda: dict(problem=_di_min_time(), tol=1e-4, method="radau", max_iterations=3, n_min=3, n_max=6,
                 max_intervals=40, extra_points=1, ipopt_options={"max_iter": 200})
)
case("optimal_control.symmetry_breaking_guess", kinds={"problem": "object"})(
    lambda: dict(problem=_di_min_time(), amplitude=0.25)
)
case("optimal_control.guess_from_function")(
    lambda: dict(fun=lambda t: ([t, 1.0], [0.0]), t0=0.0, tf=2.0, n_samples=3)
)
case("optimal_control.problems.brachistochrone", nan_ok=(*OCP_NAN, "final_state"), positive=("x_final", "drop"))(
    lambda: dict(x_final=10.0, drop=5.0)
)
case("optimal_control.problems.brachistochrone_time", positive=("x_final", "drop", "g"))(
    lambda: dict(x_final=10.0, drop=5.0, g=9.80665)
)
case("optimal_control.problems.bryson_denham", nan_ok=OCP_NAN, positive=("l",))(lambda: dict(l=1.0 / 9.0))
case("optimal_control.problems.hypersensitive", nan_ok=OCP_NAN, positive=("tf",))(lambda: dict(tf=10.0))
case("optimal_control.problems.rigid_body_reorientation", nan_ok=OCP_NAN)(lambda: dict(angle_deg=180.0))
case("optimal_control.problems.goddard_rocket", nan_ok=("*",))(lambda: dict())
case("optimal_control.problems.bang_singular_bang", nan_ok=OCP_NAN, positive=("tf",))(lambda: dict(tf=3.0))
case("optimal_control.problems.bang_singular_bang_objective", positive=("tf",))(lambda: dict(tf=3.0))
case("optimal_control.problems.rest_to_rest_mixed_path", nan_ok=(*OCP_NAN, "path_lower"), positive=("distance",))(
    lambda: dict(distance=1.0)
)
case("optimal_control.problems.rest_to_rest_mixed_path_time", positive=("distance",))(lambda: dict(distance=1.0))
case("optimal_control.problems.launch_ascent", nan_ok=("*",))(lambda: dict())


def _launch() -> Any:
    from adcskit.optimal_control.problems import launch_ascent

    return launch_ascent()


case("optimal_control.problems.launch_ascent_guess", kinds={"problem": "object"})(lambda: dict(problem=_launch()))
case("optimal_control.problems.reference_objective", aliases={"name": ("problem",)})(
    lambda: dict(name="bryson-denham")
)

# ============================================================================================
# simulation (h13sim)
# ============================================================================================

exempt(RESULT, "simulation.SimulationResult")


def _sim_scenario() -> Any:
    from adcskit.simulation import Scenario, SimSpec

    return Scenario(sim=SimSpec(dt=0.02, t_final=1.0, metrics_from_s=0.5))


case("simulation.SpacecraftSpec")(lambda: dict(inertia=(1218.6, 442.2, 1429.4)))
case("simulation.OrbitSpec", kinds={"epoch": "times"}, positive=("altitude_km",))(
    lambda: dict(altitude_km=800.0, inclination_deg=98.0, raan_deg=10.0, arg_lat0_deg=0.0,
                 epoch="2026-03-21T06:00:00", gravity_gradient=True, magnetic_model="dipole")
)
case("simulation.DisturbanceSpec", positive=("period_s",))(
    lambda: dict(constant=(1e-4, 0.0, 0.0), amplitude=(1e-4, 1e-4, 0.0), period_s=600.0, phase_deg=(0.0, 90.0, 0.0))
)


def _thr_kw() -> dict[str, Any]:
    from adcskit.simulation import ThrusterSpec

    d = _default_thr()
    return dict(positions=d.positions, directions=d.directions, f_max=10.0, mdot=3.5e-3, t_min=3e-3, tau=0.01,
                delay=0.02, com=(0.0, 0.0, 0.0), failed=(), failure_known=True) if isinstance(d, ThrusterSpec) else {}


def _default_thr() -> Any:
    from adcskit.simulation import Scenario

    return Scenario().thrusters


case("simulation.ThrusterSpec", positive=("f_max", "mdot", "t_min", "tau", "delay"), kinds={"failed": "skip"})(_thr_kw)
case("simulation.SensorSpec", positive=("sun_rate_hz", "sun_noise_deg", "mag_rate_hz", "mag_noise_deg", "gyro_rate_hz",
                                        "gyro_arw", "gyro_rrw", "star_tracker_noise_arcsec"))(
    lambda: dict(sun_rate_hz=1.0, sun_noise_deg=0.005, mag_rate_hz=1.0, mag_noise_deg=0.5, noise="gaussian",
                 gyro_rate_hz=10.0, gyro_arw=3.16e-7, gyro_rrw=3.16e-10, gyro_bias0_deg_h=1.0,
                 star_tracker_rate_hz=1.0, star_tracker_noise_arcsec=10.0)
)
case("simulation.EstimatorSpec", positive=("init_error_deg", "search_range"))(
    lambda: dict(kind="minmax", wahba_method="q-method", search_range=0.1, weights="inverse-variance",
                 init_error_deg=1.0)
)
case("simulation.GuidanceSpec")(lambda: dict(kind="step", target_rotvec_deg=(10.0, 0.0, 0.0), t_step=1.0))
case("simulation.ControllerSpec", positive=("period_s", "u_on", "torque_level"), kinds={"on_times": "skip"})(
    lambda: dict(kind="schmitt", period_s=0.2, kp=(56.24,) * 3, ki=(0.02,) * 3, kd=(49.99,) * 3, u_on=0.15,
                 off_ratio=0.5, torque_level=(10.0,) * 3, allocation="pinv-redistribute", min_on_time="drop")
)
case("simulation.DispersionSpec", positive=("inertia_rel", "thrust_rel", "misalignment_deg", "delay_std_s",
                                            "disturbance_rel", "initial_attitude_deg", "initial_rate_deg_s"))(
    lambda: dict(inertia_rel=0.05, thrust_rel=0.05, misalignment_deg=0.5, delay_std_s=0.002, disturbance_rel=0.1,
                 initial_attitude_deg=1.0, initial_rate_deg_s=0.01, sampling="lhs")
)
case("simulation.SimSpec", positive=("dt", "t_final", "settle_band_deg"))(
    lambda: dict(dt=0.02, t_final=10.0, metrics_from_s=5.0, settle_band_deg=0.5, nees_from_s=0.0, record_every=10)
)
case("simulation.Scenario", kinds={k: "object" for k in ("spacecraft", "orbit", "disturbance", "thrusters", "sensors",
                                                          "estimator", "guidance", "controller", "dispersions", "sim")})(
    lambda: dict(sim=_sim_scenario().sim, initial_rotvec_deg=(1.0, 0.0, 0.0), initial_rate_deg_s=(0.0, 0.01, 0.0))
)
case("simulation.load_scenario", aliases={"source": ("scenario", "config", "path"), "overrides": ("config",)})(
    lambda: dict(source={"sim": {"t_final": 20.0, "metrics_from_s": 10.0}}, overrides={"sim": {"dt": 0.05}})
)
case("simulation.scenario_toml", kinds={"scenario": "object"})(lambda: dict(scenario=_sim_scenario(), comments=True))
case("simulation.reference_profile", kinds={"scenario": "object"})(lambda: dict(scenario=_sim_scenario()))
def _simulate_kw() -> dict[str, Any]:
    return dict(scenario=_sim_scenario(), n_samples=2, rng=1, record=False)


case("simulation.simulate", target=_warmed("simulation.simulate", _simulate_kw), kinds={"scenario": "object", "executor": "skip", "directory": "skip"},
     nan_ok=("settling_time", "nees", "box_active_fraction"), slow=True)(
    _simulate_kw
)

# --- wheels, magnetorquers and modes (issue 25 items 1-3)

exempt(RESULT, "simulation.WheelSimulationResult")


def _wheel_scenario() -> Any:
    from adcskit.simulation import ModeSpec, SimSpec, WheelScenario

    return WheelScenario(modes=ModeSpec(initial="point", sequence=False), sim=SimSpec(dt=0.1, t_final=1.0,
                                                                                    metrics_from_s=0.5))


case("simulation.WheelSpec", positive=("inertia_kgm2", "max_torque_nm", "max_speed_rpm", "viscous_nms", "coulomb_nm",
                                       "torque_quantum_nm", "torque_noise_nm"), kinds={"failed": "skip"})(
    lambda: dict(axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.577, 0.577, 0.577)), inertia_kgm2=2.4e-5,
                 max_torque_nm=4e-3, max_speed_rpm=6000.0, viscous_nms=1e-8, coulomb_nm=1e-5, torque_quantum_nm=1e-6,
                 torque_noise_nm=1e-6, initial_speed_rpm=100.0, failed=(3,))
)
case("simulation.WheelSpec.pyramid", target=lambda: __import__("adcskit.simulation", fromlist=["WheelSpec"]).WheelSpec.pyramid,
     positive=("elevation_deg", "max_torque_nm"))(lambda: dict(elevation_deg=35.0, max_torque_nm=4e-3))
case("simulation.WheelSpec.axis_matrix", target=method("", lambda: __import__(
    "adcskit.simulation", fromlist=["WheelSpec"]).WheelSpec(), "axis_matrix"))(lambda: dict())
case("simulation.MagnetorquerSpec", positive=("max_dipole_am2", "duty", "coupling_t_per_am2", "bdot_gain", "unload_gain"))(
    lambda: dict(max_dipole_am2=0.2, duty=0.8, magnetometer="corrupt", coupling_t_per_am2=1e-6, bdot_gain=2e5,
                 unload_gain=2e-3)
)
case("simulation.WheelControlSpec", positive=("bandwidth_rad_s", "damping", "rate_limit_deg_s", "period_s", "null_gain",
                                              "null_speed_rpm"), kinds={"open_loop_torque_nm": "skip"})(
    lambda: dict(law="wie", bandwidth_rad_s=0.1, damping=0.9, rate_limit_deg_s=1.0, period_s=0.5, null_motion=True,
                 null_gain=0.01, null_speed_rpm=1000.0)
)
case("simulation.ModeSpec", positive=("rate_threshold_deg_s", "dwell_s", "sun_threshold_deg"))(
    lambda: dict(initial="detumble", sequence=True, rate_threshold_deg_s=1.0, dwell_s=60.0, sun_axis=(0.0, 0.0, 1.0),
                 sun_threshold_deg=10.0, pointing="inertial", target_rotvec_deg=(10.0, 0.0, 0.0))
)
case("simulation.WheelDispersionSpec", positive=("inertia_rel", "wheel_misalignment_deg", "sensor_noise_rel",
                                                 "initial_rate_deg_s", "initial_attitude_deg"))(
    lambda: dict(inertia_rel=0.1, wheel_misalignment_deg=0.5, sensor_noise_rel=0.2, initial_rate_deg_s=1.0,
                 initial_attitude="nominal", initial_attitude_deg=5.0, sampling="lhs")
)
def _unload_kw() -> dict[str, Any]:
    from adcskit.simulation import ThrusterSpec

    pos = ((0.1, 0.0, 0.0), (-0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.0, -0.1, 0.0), (0.0, 0.0, 0.15), (0.0, 0.0, -0.15))
    d = ((0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0))
    jets = ThrusterSpec(positions=pos + pos, directions=d + tuple((-a, -b, -c) for a, b, c in d), f_max=0.01,
                        mdot=1.4e-5, t_min=0.01)
    return dict(thrusters=jets, start_nms=0.01, stop_nms=0.002, torque_nm=5e-4)


case("simulation.ThrusterUnloadSpec", positive=("start_nms", "stop_nms", "torque_nm"), kinds={"thrusters": "object"})(
    _unload_kw)
case("simulation.ThrusterUnloadSpec.torque_matrix", target=method("", lambda: __import__(
    "adcskit.simulation", fromlist=["ThrusterUnloadSpec"]).ThrusterUnloadSpec(**_unload_kw()), "torque_matrix"))(
    lambda: dict())
case("simulation.WheelScenario", kinds={k: "object" for k in ("spacecraft", "orbit", "disturbance", "wheels",
                                                              "magnetorquers", "sensors", "control", "modes",
                                                              "dispersions", "sim", "thruster_unloading",
                                                              "estimator")})(
    lambda: dict(sim=_wheel_scenario().sim, initial_rotvec_deg=(1.0, 0.0, 0.0), initial_rate_deg_s=(0.0, 0.01, 0.0),
                 thruster_unloading=__import__("adcskit.simulation", fromlist=["ThrusterUnloadSpec"]).ThrusterUnloadSpec(
                     **_unload_kw()),
                 estimator=__import__("adcskit.simulation", fromlist=["EstimatorSpec"]).EstimatorSpec(kind="mekf"))
)
case("simulation.load_wheel_scenario", aliases={"source": ("scenario", "config", "path"), "overrides": ("config",)})(
    lambda: dict(source={"sim": {"t_final": 20.0, "metrics_from_s": 10.0}}, overrides={"sim": {"dt": 0.05}})
)


def _simulate_wheels_kw() -> dict[str, Any]:
    return dict(scenario=_wheel_scenario(), n_samples=2, rng=1, record=False, chunk_size=1)


def _wheel_result() -> Any:
    from adcskit.simulation import simulate_wheels

    return simulate_wheels(**_simulate_wheels_kw())


case("simulation.WheelSimulationResult.check_requirements", target=method("", _wheel_result, "check_requirements"),
     kinds={"requirements": "skip"})(lambda: dict(requirements=["max_rate_deg_s max <= 10"], method="wilson"))
def _wheel_recorded() -> Any:
    from adcskit.simulation import simulate_wheels

    return simulate_wheels(**(_simulate_wheels_kw() | {"record": True}))


case("simulation.WheelSimulationResult.envelope", target=method("", _wheel_recorded, "envelope"),
     nan_ok=("*",))(lambda: dict(channel="rate"))
case("simulation.wheel_envelope_figure", kinds={"result": "object"})(lambda: dict(result=_wheel_recorded(), channels=["rate"]))
case("simulation.simulate_wheels", target=_warmed("simulation.simulate_wheels", _simulate_wheels_kw),
     kinds={"scenario": "object", "executor": "skip", "directory": "skip"}, nan_ok=("t_detumbled_s", "t_acquired_s", "settling_time_s"), slow=True)(
    _simulate_wheels_kw
)

# ============================================================================================
# public methods (issue 23: every public name, methods of public classes included; the gap is
# listed by ``public_gap.py`` and checked by ``test_every_public_name_has_an_entry``)
# ============================================================================================


def _ts() -> Any:
    from adcskit.thrusters import ThrusterSet

    return ThrusterSet(positions=POS, directions=DIRS, f_max=10.0, t_min=0.003, mdot=0.0035)


def _spacecraft() -> Any:
    from adcskit.simulation import SpacecraftSpec

    return SpacecraftSpec(inertia=(1218.6, 442.2, 1429.4))


# methods without arguments: the valid call on a validated object must give finite numbers
for _name, _make, _meth in (
    ("thrusters.ThrusterSet.angles", _ts, "angles"),
    ("thrusters.ThrusterSet.force_matrix", _ts, "force_matrix"),
    ("thrusters.ThrusterSet.lever_arms", _ts, "lever_arms"),
    ("thrusters.ThrusterSet.torque_matrix", _ts, "torque_matrix"),
    ("simulation.SpacecraftSpec.matrix", _spacecraft, "matrix"),
    ("simulation.ThrusterSpec.torque_matrix", _default_thr, "torque_matrix"),
    ("optimal_control.Mesh.label", _mesh24, "label"),
    ("optimal_control.OptimalControlProblem.scales", _di, "scales"),
    ("optimal_control.Phase.scales", lambda: _phases()[0], "scales"),
):
    case(_name, target=method("", _make, _meth), nan_ok=("*",) if "scales" in _name else ())(lambda: dict())

case("optimal_control.Mesh.uniform")(lambda: dict(n_intervals=2, n_nodes=4))


def _thrusters_list() -> list[Any]:
    from adcskit.thrusters import Thruster

    return [Thruster(position=p, direction=d, f_max=10.0) for p, d in zip(POS, DIRS)]


case("thrusters.ThrusterSet.from_thrusters", kinds={"thrusters": "object"})(
    lambda: dict(thrusters=_thrusters_list(), com=(0.0, 0.0, 0.1))
)
case("simulation.ThrusterSpec.from_thruster_set", kinds={"ts": "object"}, positive=("tau", "delay"))(
    lambda: dict(ts=_ts(), tau=0.01, delay=0.02)
)
case("simulation.ThrusterSpec.from_torque_matrix", positive=("f_max", "tau", "delay"), kinds={"failed": "skip"})(
    lambda: dict(A=_default_thr().torque_matrix(), f_max=10.0, tau=0.01, delay=0.02)
)


def _sun() -> Any:
    from adcskit.sensors import SunSensor

    return SunSensor(**SENSOR_KW)


case("sensors.SunSensor.measure", target=method("", _sun, "measure"),
     degenerate={"zero-attitude": {"A": np.zeros((3, 3))}, "zero-ref": {"r": [0.0, 0.0, 0.0]}})(
    lambda: dict(A=[list(r) for r in A_ATT], r=list(R_REF), rng=3, eclipse=False)
)


_POOL: list[Any] = []


def _process_map() -> Callable[..., Any]:
    # one worker process for every mutation (a pool per call would leave processes behind)
    if not _POOL:
        import atexit

        from adcskit.uncertainty import ProcessExecutor

        _POOL.append(ProcessExecutor(n_workers=1))
        atexit.register(_POOL[0].close)
    return _POOL[0].map


case("uncertainty.ProcessExecutor.map", target=_process_map, kinds={"description": "skip", "tasks": "object"},
     nan_ok=("*",), nonfinite_ok=("fn",), slow=True)(lambda: dict(fn=_square, tasks=[1.0, 2.0]))
case("uncertainty.ProcessExecutor.close", target=method("", lambda: __import__(
    "adcskit.uncertainty", fromlist=["x"]).ProcessExecutor(n_workers=1), "close"))(lambda: dict())

# --- methods of result dataclasses that take input (the results themselves are exempt) ------

exempt(
    "accessor without arguments of a result built by adcskit (nothing to validate)",
    "studies.StudyResult.all_claims",
)
exempt(
    "dataclasses.replace of the adaptive-refinement fields, called by solve_adaptive on its own "
    "result (keyword names are checked by dataclasses.replace)",
    "optimal_control.MultiPhaseSolution.with_adaptive",
)


def _onoff_metrics() -> Any:
    from adcskit.control import simulate_batch

    return simulate_batch(_params(), _settings(), backend="numba", parallel=False)


def _wahba_result() -> Any:
    from adcskit.determination import solve_wahba

    return solve_wahba(np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))


def _mp_solution() -> Any:
    if "mp" not in _SOL:
        from adcskit.optimal_control import solve_multiphase

        _SOL["mp"] = solve_multiphase(_mp(), method="radau", meshes=[(1, 3), (1, 3)])
    return _SOL["mp"]


case("control.OnOffMetrics.as_array", target=method("", _onoff_metrics, "as_array"), nan_ok=("*",))(lambda: dict())
case("determination.WahbaResult.messages", target=method("", _wahba_result, "messages"))(lambda: dict())
case("optimal_control.OptimalControlSolution.as_guess", target=method("", _solution, "as_guess"))(lambda: dict())
case("optimal_control.MultiPhaseSolution.as_guess", target=method("", _mp_solution, "as_guess"), slow=True)(
    lambda: dict())
for _meth in ("state_at", "costate_at"):
    case(f"optimal_control.OptimalControlSolution.{_meth}", target=method("", _solution, _meth))(
        lambda: dict(t=[0.1, 0.5, 0.9]))
case("optimal_control.OptimalControlSolution.control_at", target=method("", _solution, "control_at"))(
    lambda: dict(t=[0.1, 0.5, 0.9], kind="lagrange"))


# ============================================================================================
# uncertainty: requirement statistics (issue 25 item 4) -- kept as one block for easy merging
# ============================================================================================

exempt(RESULT, "uncertainty.PercentileBound", "uncertainty.ProportionInterval", "uncertainty.RequirementVerdict",
       "uncertainty.RequirementTable")
_REQ_X = [0.01 * i for i in range(1, 60)]  # 59 samples: enough for a 95/95 bound
case("uncertainty.percentile_bound", nonfinite_ok=("x",), positive=("percentile", "confidence"), shape_stable=False,
     nan_ok=("lower", "upper", "achieved_confidence"))(
    lambda: dict(x=list(_REQ_X), percentile=95.0, confidence=0.95, side="upper"))
case("uncertainty.proportion_interval", positive=("k", "n", "confidence"))(
    lambda: dict(k=3, n=100, confidence=0.95, method="clopper-pearson", side="two-sided"))
case("uncertainty.exceedance_probability", nonfinite_ok=("x",), positive=("confidence",))(
    lambda: dict(x=list(_REQ_X), threshold=0.5, comparison=">", confidence=0.95, method="wilson", side="upper"))
case("uncertainty.samples_needed", positive=("coverage", "confidence", "failures"))(
    lambda: dict(coverage=0.95, confidence=0.95, failures=1, side="two-sided"))
case("uncertainty.Requirement", positive=("percentile", "confidence", "after_s"), kinds={"metric": "skip", "name": "skip"},
     extra={"bad-metric": ("metric", "pointing error", "type"), "int-name": ("name", 3, "type")})(
    lambda: dict(metric="pointing_max_deg", statistic="percentile", comparison="<=", threshold=0.1, percentile=99.0,
                 confidence=0.95, after_s=300.0, name="ADCS-1"))
case("uncertainty.parse_requirement", kinds={"text": "skip"}, positive=("confidence",),
     extra={"garbled": ("text", "pointing_max_deg p99 0.1", "type"), "no-text": ("text", None, "type")})(
    lambda: dict(text="ADCS-1: P(pointing_max_deg > 0.1) <= 1 % after 300 s", confidence=0.9))
case("uncertainty.read_requirements", kinds={"source": "object"}, positive=("confidence",),
     extra={"bad-line": ("source", ["x p99 <= 0.1", "x p99 0.1"], "type"),
            "unknown-key": ("source", [{"metric": "x", "statistic": "max", "comparison": "<=", "threshold": 1.0,
                                         "unit": "deg"}], "type")})(
    lambda: dict(source=["x p99 <= 0.1 after 300 s", {"text": "x mean <= 0.05", "name": "R2"}], confidence=0.95))
# metrics is a simulation's metric table: metrics no requirement reads are normal (open keys)
case("uncertainty.check_requirements", kinds={"requirements": "object"}, aliases={"requirements": ("source",)},
     open_keys=("metrics",),
     positive=("metrics_from_s",), shape_stable=False, nan_ok=("bound", "opposite_bound"),
     extra={"nan-metric": ("metrics", {"pointing_max_deg": [0.01, float("nan")]}, "type"),
            "2d-metric": ("metrics", {"pointing_max_deg": [[0.01, 0.02]]}, "type")})(
    lambda: dict(requirements=["pointing_max_deg p99 <= 0.1 after 300 s", "P(pointing_max_deg > 0.05) <= 0.5"],
                 metrics={"pointing_max_deg": list(_REQ_X)}, metrics_from_s=300.0, method="clopper-pearson",
                 nan_policy="raise"))

# --- names new on main at 7bc2210 (merged into h-robust): optimality check, problems ---------

exempt(RESULT, "optimal_control.OptimalityCheck")
exempt(
    "accessor without arguments of a result built by adcskit (nothing to validate)",
    "uncertainty.RequirementTable.table_rows",
    "uncertainty.RequirementVerdict.table_row",
)
case("optimal_control.check_optimality", kinds={"solution": "object"}, positive=("threshold",), nan_ok=("*",))(
    lambda: dict(solution=_solution(), threshold=1e-2)
)
case("optimal_control.default_optimality_threshold", positive=("tol",))(lambda: dict(tol=1e-4))
case("optimal_control.problems.free_flying_robot", nan_ok=("*",))(lambda: dict())
case("optimal_control.problems.oscillator_min_time", nan_ok=("*",))(lambda: dict(x0=7.0, v0=0.5))
case("optimal_control.problems.orbit_raising", nan_ok=("*",))(lambda: dict())
case("optimal_control.problems.robot_arm", nan_ok=("*",))(lambda: dict())
# the number of switching times depends on the start state (none at the origin)
case("optimal_control.problems.oscillator_min_time_reference", shape_stable=False)(lambda: dict(x0=7.0, v0=0.5))


def _guess() -> Any:
    from adcskit.optimal_control import Guess

    return Guess(t=[0.0, 0.5, 1.0], x=[[0.0, 0.0], [0.5, 1.0], [1.0, 0.0]], u=[[1.0], [0.0], [-1.0]], tf=1.0)


case("optimal_control.Guess.check_widths", target=method("", _guess, "check_widths"), kinds={"what": "skip"})(
    lambda: dict(n_states=2, n_controls=1)
)

# ============================================================================================
# simulation: export, envelope figures, sign-off (issue 25 item 5) -- kept as one block
# ============================================================================================

exempt(RESULT, "simulation.SignOffTable")
exempt("accessor without arguments of a result built by adcskit (nothing to validate)",
       "simulation.SignOffTable.table_rows", "simulation.SignOffTable.to_markdown", "simulation.SignOffTable.to_text")
_SIM_RECORDED: list[Any] = []


def _sim_recorded() -> Any:
    """One tiny recorded campaign shared by the cases below (built once; never modified)."""
    if not _SIM_RECORDED:
        from adcskit.simulation import simulate

        _SIM_RECORDED.append(simulate(_sim_scenario(), n_samples=4, rng=1, record=True))
    return _SIM_RECORDED[0]


_XR = {"nan_ok": ("*",)}  # a Dataset's leaves are not walked; settling times may be NaN
case("simulation.to_dataset", kinds={"result": "object", "scenario": "object"}, positive=("rng_seed",), **_XR)(
    lambda: dict(result=_sim_recorded(), scenario=_sim_scenario(), rng_seed=1))
case("simulation.write_netcdf", kinds={"result": "object", "scenario": "object", "path": "path"}, positive=("rng_seed",),
     **_XR)(lambda: dict(result=_sim_recorded(), path=scratch_path("nc", file_suffix=".nc"), scenario=_sim_scenario(),
                         rng_seed=1))
case("simulation.write_zarr", kinds={"result": "object", "scenario": "object", "path": "path"}, positive=("rng_seed",),
     slow=True, **_XR)(lambda: dict(result=_sim_recorded(), path=scratch_path("zarr") + "/run.zarr", scenario=_sim_scenario()))


def _nc_file() -> str:
    from adcskit.simulation import write_netcdf

    return str(write_netcdf(_sim_recorded(), scratch_path("nc-read", file_suffix=".nc")))


case("simulation.read_dataset", kinds={"path": "path"}, **_XR)(lambda: dict(path=_nc_file()))
case("simulation.envelope_figure", kinds={"result": "object", "channel": "skip", "units": "skip", "label": "skip"},
     extra={"unknown-channel": ("channel", "wheel_speed", "type")}, slow=True)(
    lambda: dict(result=_sim_recorded(), channel="pointing_error", scale=57.29577951308232, units="deg",
                 label="pointing error", worst=2, worst_by="pointing_max_deg", yscale="log", t_from=0.0))
# figures take ~0.1 s each: every mutation runs in the exhaustive variant (-m slow) only
case("simulation.attitude_error_figure", kinds={"result": "object"}, slow=True)(
    lambda: dict(result=_sim_recorded(), worst=2, worst_by="pointing_max_deg", axes=True, yscale="log", t_from=0.0))
case("simulation.body_rate_figure", kinds={"result": "object"}, slow=True)(
    lambda: dict(result=_sim_recorded(), worst=1, worst_by="max_rate_deg_s", t_from=0.0))
case("simulation.check_simulation", kinds={"requirements": "object", "result": "object", "scenario": "object"},
     aliases={"requirements": ("source", "requirement")}, positive=("confidence",), shape_stable=False,
     nan_ok=("bound", "opposite_bound", "estimate"),
     extra={"bad-line": ("requirements", ["pointing_max_deg p99 0.1"], "type"),
            "unknown-metric": ("requirements", ["pointing_worst_deg p95 <= 1"], "type"),
            "window-out-of-run": ("requirements", ["pointing_max_deg p95 <= 1 after 50 s"], "type")})(
    lambda: dict(requirements=["R1: pointing_max_deg p95 <= 1 after 0.5 s", "P(final_error_deg > 2) <= 5 %"],
                 result=_sim_recorded(), scenario=_sim_scenario(), confidence=0.95, method="clopper-pearson",
                 nan_policy="fail"))
