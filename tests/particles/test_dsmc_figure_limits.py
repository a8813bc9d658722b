"""The a2 criterion of the DSMC figures is the 3-sigma level of its t distribution."""
from scipy.stats import t

from particles.figures.dsmc import A2_T_LIMIT


def test_a2_limit_is_students_t_3_sigma_for_10_batches():
    # the a2 error comes from 10 batch means: 9 degrees of freedom
    assert abs(A2_T_LIMIT - t.ppf(0.99865, 9)) < 0.01
