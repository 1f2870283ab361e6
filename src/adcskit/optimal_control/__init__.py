"""Pseudospectral optimal control: Gauss (LG) and Radau (LGR) multi-interval transcriptions
solved by CasADi + IPOPT, error-controlled hp mesh refinement (:func:`solve_adaptive`),
multi-phase problems with links, events, static parameters and integral constraints
(:func:`solve_multiphase`), costate estimation from the KKT multipliers, Hamiltonian,
bang-bang detection and open-loop re-simulation. See docs/optimal-control.md.

Typical use::

    from adcskit.optimal_control import solve, solve_mesh_sequence, bang_bang, resimulate
    from adcskit.optimal_control.problems import rendezvous_problem

    sol = solve(rendezvous_problem([20, 0, 0]), method="gauss", mesh=(20, 3))
    sol.success, sol.status, sol.tf, sol.hamiltonian.mean()

References
----------
S2 (Gauss pseudospectral method, eq. 17–37). Benson et al. 2006; Garg et al. 2010.
"""

from adcskit.optimal_control._nlp import clear_cache
from adcskit.optimal_control.adaptive import (
    AdaptiveSolution,
    ErrorCertificate,
    MeshIteration,
    default_optimality_threshold,
    estimate_error,
    guess_from_function,
    refine_mesh,
    solve_adaptive,
    symmetry_breaking_guess,
)
from adcskit.optimal_control.analysis import (
    BangBangResult,
    OptimalityCheck,
    ResimulationResult,
    bang_bang,
    check_optimality,
    resimulate,
)
from adcskit.optimal_control.multiphase import (
    Endpoint,
    Link,
    MultiPhaseGuess,
    MultiPhaseProblem,
    MultiPhaseSolution,
    Phase,
    default_multiphase_guess,
    solve_multiphase,
)
from adcskit.optimal_control.nodes import (
    gauss_differentiation_matrix,
    lagrange_derivative_matrix,
    lagrange_matrix,
    legendre_gauss,
    legendre_gauss_radau,
    radau_differentiation_matrix,
)
from adcskit.optimal_control.problem import Guess, Mesh, OptimalControlProblem
from adcskit.optimal_control.solve import (
    WARM_START_IPOPT_OPTIONS,
    MeshSequenceResult,
    MultistartResult,
    NLPPoint,
    OptimalControlSolution,
    default_guess,
    multistart,
    random_guess,
    solve,
    solve_mesh_sequence,
)
from adcskit.optimal_control.transcription import DEFAULT_IPOPT_OPTIONS, METHODS

__all__ = [
    "AdaptiveSolution",
    "BangBangResult",
    "OptimalityCheck",
    "Endpoint",
    "ErrorCertificate",
    "Link",
    "MeshIteration",
    "MultiPhaseGuess",
    "MultiPhaseProblem",
    "MultiPhaseSolution",
    "Phase",
    "default_multiphase_guess",
    "default_optimality_threshold",
    "estimate_error",
    "guess_from_function",
    "refine_mesh",
    "solve_adaptive",
    "solve_multiphase",
    "symmetry_breaking_guess",
    "DEFAULT_IPOPT_OPTIONS",
    "Guess",
    "METHODS",
    "Mesh",
    "MeshSequenceResult",
    "MultistartResult",
    "NLPPoint",
    "OptimalControlProblem",
    "OptimalControlSolution",
    "ResimulationResult",
    "WARM_START_IPOPT_OPTIONS",
    "bang_bang",
    "check_optimality",
    "clear_cache",
    "default_guess",
    "gauss_differentiation_matrix",
    "lagrange_derivative_matrix",
    "lagrange_matrix",
    "legendre_gauss",
    "legendre_gauss_radau",
    "multistart",
    "radau_differentiation_matrix",
    "random_guess",
    "resimulate",
    "solve",
    "solve_mesh_sequence",
]
