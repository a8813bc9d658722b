"""Figures and claims of the paper that need particle simulations (DSMC, MD)."""

from . import dsmc, md, mixture  # noqa: F401
