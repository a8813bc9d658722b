"""Analytic first-order Sonine results: the a2(alpha) line and its elastic limit (C3)."""

from __future__ import annotations

import numpy as np

from ..reproduce import ClaimRow, Context, register
from ..sonine import A2_ELASTIC_LIMIT, a2_first_order
from .plotting import save, subplots


@register("S1", "first-order Sonine a2(alpha) and its alpha -> 1 limit", claims=("C3",))
def sonine_line(ctx: Context) -> list[ClaimRow]:
    """Plot a2_first_order over [0, 1] and check the limit -16/159."""

    alpha = np.linspace(0.0, 1.0, 201)
    fig, ax = subplots(figsize=(5, 3.5))
    ax.plot(alpha, a2_first_order(alpha), "k-", label="first-order Sonine")
    ax.axhline(A2_ELASTIC_LIMIT, color="gray", ls=":", label="-16/159")
    ax.set_xlabel(r"$\alpha$")
    ax.set_ylabel(r"$a_2$")
    ax.legend()
    save(fig, ctx.out / "S1_a2_first_order.png")
    limit = float(a2_first_order(1.0 - 1e-12))
    return [ClaimRow("C3", "a2_first_order(alpha -> 1)", f"{limit:.12f}",
                     f"-16/159 = {A2_ELASTIC_LIMIT:.12f}",
                     bool(abs(limit - A2_ELASTIC_LIMIT) < 1e-10), "sonine (analytic)")]
