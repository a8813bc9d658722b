"""Reproduce item B3 (particles.figures.mixture): registered, its rows from the numbers."""

import math

import pytest

from kinetic_fem.reproduce import ITEMS, Context, load_plugins
from particles.figures import mixture as fig


def test_b3_is_registered():
    load_plugins()
    assert "B3" in ITEMS and ITEMS["B3"].run is fig.mixture_temperature_ratio


def test_b3_rows_state_where_sonine_is_off_by_more_than_one_percent(tmp_path):
    points = [
        {"mass_ratio": 0.1, "sonine": 2.0, "dsmc": 2.1, "dsmc_error": 0.01, "md": 2.5,
         "md_error": 0.05, "fem": math.nan},
        {"mass_ratio": 1.0, "sonine": 1.0, "dsmc": 1.02, "dsmc_error": 0.01, "md": 1.0,
         "md_error": 0.01, "fem": math.nan},
        {"mass_ratio": 10.0, "sonine": 0.5, "dsmc": 0.502, "dsmc_error": 0.01,
         "md": math.nan, "md_error": math.nan, "fem": math.nan}]
    rows = fig._rows("same_power", 0.7, points, Context(out=tmp_path, quick=True))
    sonine, md = rows
    assert "4.76 %" in sonine.measured and "m2/m1=0.1" in sonine.measured
    assert sonine.note.endswith("[0.1]")  # 1.0: 2 % but |z| = 2, 10: 0.4 %
    assert sonine.method == "dsmc" and sonine.agrees is None
    assert md.measured == "z = +7.8 (m2/m1=0.1)"
    with_fem = [{**p, "fem": p["dsmc"]} for p in points]
    assert fig._rows("same_power", 0.7, with_fem, Context(out=tmp_path))[0].method == "fem"


@pytest.mark.slow
def test_b3_quick_run(tmp_path):
    rows = fig.mixture_temperature_ratio(Context(out=tmp_path, quick=True))
    assert len(rows) == 12
    assert (tmp_path / "B3_mixture_temperature_ratio.png").exists()
    assert (tmp_path / "B3_mixture_temperature_ratio.csv").read_text().count("\n") == 19
