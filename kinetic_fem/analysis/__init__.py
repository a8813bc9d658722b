"""Analysis of solutions: tail exponents and their peaks, tail and relaxation fits,
Richardson extrapolation.  Every function takes :class:`~kinetic_fem.VelocityDistribution`
results (of any method) and returns numbers or small frozen records."""

from .exponent import (
    F_ANALYSIS_FLOOR,
    ExponentPeak,
    exponent_peak,
    local_exponents,
    power_law_exponent,
)
from .extrapolation import richardson
from .fits import TailFit, relaxation_fit, tail_fit
from .humps import HumpProfile, psi_profile

__all__ = ["F_ANALYSIS_FLOOR", "ExponentPeak", "exponent_peak", "local_exponents",
           "power_law_exponent", "richardson", "TailFit", "relaxation_fit", "tail_fit",
           "HumpProfile", "psi_profile"]
