"""Kalman filtering and model identification (S1).

* :func:`kalman_filter` / :class:`KalmanFilter` — linear Kalman filter, standard
  predict/update and the one-step predictor of S1 eq. (18) (Joseph-form covariances);
  :func:`simulate_linear` — seeded linear simulation.
* :func:`identify_model` — least-squares identification of ``A`` (and ``B``) with the
  solver registry :data:`IDENTIFICATION_METHODS` (QR, Krylov, LSQR, S1's offline/online
  adaptive GMRES, ridge toward the prior, RLS).
* :func:`joint_estimate` — S1's alternation of Kalman filtering and identification;
  :func:`augmented_ekf` — joint state/parameter EKF baseline.
* :func:`mekf_filter` / :class:`MultiplicativeEKF` — multiplicative EKF for attitude with
  gyro-bias estimation (Lefferts, Markley & Shuster 1982), batched over Monte-Carlo samples
  in compiled code, with NEES/NIS statistics (:func:`chi2_band`).
"""

from adcskit.estimation.identification import (
    IDENTIFICATION_METHODS,
    IdentificationResult,
    RecursiveLeastSquares,
    identify_model,
    offline_schedule,
    regression_data,
)
from adcskit.estimation.joint import AugmentedEKFResult, JointResult, augmented_ekf, joint_estimate
from adcskit.estimation.kalman import (
    KALMAN_FORMS,
    KalmanFilter,
    KalmanResult,
    LinearSimulation,
    kalman_filter,
    simulate_linear,
)
from adcskit.estimation.mekf import MEKFResult, MultiplicativeEKF, chi2_band, mekf_filter

__all__ = [
    "IDENTIFICATION_METHODS",
    "KALMAN_FORMS",
    "AugmentedEKFResult",
    "IdentificationResult",
    "JointResult",
    "KalmanFilter",
    "KalmanResult",
    "LinearSimulation",
    "MEKFResult",
    "MultiplicativeEKF",
    "RecursiveLeastSquares",
    "augmented_ekf",
    "chi2_band",
    "identify_model",
    "joint_estimate",
    "kalman_filter",
    "mekf_filter",
    "offline_schedule",
    "regression_data",
    "simulate_linear",
]
