"""Richardson extrapolation of distributions on nested grids."""

from __future__ import annotations

import numpy as np

from ..distribution import VelocityDistribution

__all__ = ["richardson"]


def richardson(coarse: VelocityDistribution, fine: VelocityDistribution
               ) -> VelocityDistribution:
    """:math:`(4\\ln P_{h/2} - \\ln P_h)/3` on the nodes of ``coarse`` (nested grids).

    Parameters
    ----------
    coarse, fine : VelocityDistribution
        Second-order solutions at spacings ``h`` and ``h/2`` on nested grids.

    Returns
    -------
    VelocityDistribution
        The extrapolated distribution on the nodes of ``coarse``.
    """
    pf, pc = fine.values[::2], coarse.values
    if pf.size != pc.size:
        raise ValueError("Richardson extrapolation needs nested grids (same cut-off)")
    out = pf.copy()
    ok = (pf > 0) & (pc > 0)
    out[ok] = np.exp((4.0 * np.log(pf[ok]) - np.log(pc[ok])) / 3.0)
    return VelocityDistribution.from_values(coarse.v, out, method="fd",
                                            params={**coarse.params, "richardson": True})
