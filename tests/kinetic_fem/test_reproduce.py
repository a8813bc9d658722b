"""Tests of kinetic_fem.reproduce: the registry of figures and claims."""

import csv

import pytest

from kinetic_fem import reproduce
from kinetic_fem.reproduce import ITEMS, ClaimRow, Context, load_plugins, run_items, write_table


@pytest.fixture
def toy_item():
    calls = []

    @reproduce.register("Z9", "a toy item", claims=("C99",))
    def run(ctx):
        calls.append(ctx)
        (ctx.out / "Z9.png").write_bytes(b"png")
        return [ClaimRow("C99", "x", "1.0", "1", True, "toy", "a | pipe")]

    yield calls
    ITEMS.pop("Z9")


def test_plugins_register_the_first_items():
    loaded = load_plugins()
    assert "kinetic_fem.figures" in loaded and "particles.figures" in loaded
    assert "S1" in ITEMS and "C3" in ITEMS["S1"].claims


def test_run_and_table(tmp_path, toy_item):
    ctx = Context(out=tmp_path / "out", quick=True, seed=5)
    rows = run_items(ctx, ["Z9"])
    assert toy_item == [ctx] and rows[0].claim == "C99"
    assert (ctx.out / "Z9.png").exists()
    csv_path, md_path = write_table(rows, ctx.out)
    with csv_path.open() as fh:
        table = list(csv.DictReader(fh))
    assert table == [{"claim": "C99", "quantity": "x", "measured": "1.0", "paper": "1",
                      "agrees": "True", "method": "toy", "note": "a | pipe", "explained": ""}]
    text = md_path.read_text()
    assert text.startswith("| claim | quantity | measured | paper | agrees |")
    assert "| C99 | x | 1.0 | 1 | yes | toy |" in text


def test_unknown_item_and_double_registration(tmp_path, toy_item):
    with pytest.raises(ValueError, match=r"unknown reproduce item\(s\) \['F99'\]"):
        run_items(Context(out=tmp_path), ["F99"])
    with pytest.raises(ValueError, match="registered twice"):
        reproduce.register("Z9", "again")(lambda ctx: [])


def test_items_run_in_figure_order():
    keys = ["F10", "C2", "F2", "S1", "F1"]
    assert sorted(keys, key=reproduce.item_order) == ["C2", "F1", "F2", "F10", "S1"]


def test_sonine_item_checks_c3(tmp_path):
    """The first figure: a2_first_order over alpha and the limit -16/159 (C3)."""
    load_plugins()
    rows = run_items(Context(out=tmp_path), ["S1"])
    assert [r.claim for r in rows] == ["C3"] and rows[0].agrees is True
    assert (tmp_path / "S1_a2_first_order.png").stat().st_size > 1000


def test_quick_mode_warnings_are_summarised_once(tmp_path, capsys, caplog, monkeypatch):
    """Quick mode: an item's warnings are not printed; its rows say they are estimates.

    The markdown table shortens the note; the summary at its end names the rows once;
    the CSV keeps the warning text.  Full mode shows the warnings as they come.
    """
    import logging

    log = logging.getLogger("particles.toy")

    @reproduce.register("Z8", "a toy item that warns", claims=("C98",))
    def run(ctx):
        for n in range(3):
            log.warning("batches %d too short: error bars too small", n)
        return [ClaimRow("C98", "y", "2", "2", True, "toy")]

    root = logging.getLogger()
    handler = logging.StreamHandler()  # as a CLI would install
    # only this handler: one left by an earlier test of the same process (bound to a
    # capture stream that is closed by now) would print a logging error here
    monkeypatch.setattr(root, "handlers", [handler])
    monkeypatch.setattr(logging.getLogger("particles"), "handlers", [])
    before = {name: list(logging.getLogger(name).handlers) for name in ("particles", "")}
    try:
        ctx = Context(out=tmp_path / "q", quick=True)
        rows = run_items(ctx, ["Z8"])
        assert capsys.readouterr().err == ""  # nothing printed
        assert rows[0].note == ("quick-mode estimate (3 warnings in Z8: batches 0 too "
                                "short: error bars too small)")
        csv_path, md_path = write_table(rows, ctx.out)
        text = md_path.read_text()
        assert "| toy | quick-mode estimate |" in text
        assert text.count("Quick-mode estimates: 1 row (claims C98)") == 1
        assert "logged 3 warnings" in text and "batches 0 too short" in text
        assert "batches 0 too short" in csv_path.read_text()
        full = run_items(Context(out=tmp_path / "f", quick=False), ["Z8"])
        assert full[0].note == "" and "batches 2 too short" in capsys.readouterr().err
        assert not handler.filters  # everything put in place is removed again
        assert before == {name: logging.getLogger(name).handlers for name in before}
    finally:
        root.removeHandler(handler)
        ITEMS.pop("Z8")


@pytest.mark.slow
def test_fem_hump_items_quick(tmp_path):
    """F9-HCS (FEM hump panel, C9) and F11-HCS from the FEM cooling state, quick mode
    (eps = 1e-2, 1e-3 at 0.14 hump widths; about a minute)."""
    load_plugins()
    rows = run_items(Context(out=tmp_path, quick=True, seed=1), ["F11-HCS"])
    assert (tmp_path / "F11-HCS_psi.png").exists()
    assert {r.claim for r in rows} == {"C11", "C12"}
    assert all(r.agrees for r in rows), rows
    assert all(r.method.startswith("fem") for r in rows)


def test_verdict_summary_separates_paper_errors_quick_mode_and_unexplained_rows():
    from kinetic_fem.reproduce import QUICK_MARK, classify, verdict_summary

    rows = [ClaimRow("C1", "T", "1", "1", True),
            ClaimRow("C6", "x*", "grows", "constant", False, explained="peak exponent"),
            ClaimRow("C12", "slope", "-1", "-2", False, explained="misprint"),
            ClaimRow("C2", "tau", "-0.5", "-2/3", False,
                     note=f"{QUICK_MARK} (3 warnings in C2-DSMC: batches too short)"),
            ClaimRow("C9", "hump", "one", "two", None)]
    assert [classify(r) for r in rows] == ["agrees", "paper: peak exponent", "paper: misprint",
                                           "quick-mode sizes", "not decided"]
    text = verdict_summary(rows)
    assert "5 claim row(s): 1 agree with the paper, 1 not decided" in text
    assert "3 disagree" in text and text.endswith("0 unexplained")
    bad = ClaimRow("C4", "tail", "2", "1.5", False)
    assert verdict_summary([*rows, bad]).endswith(
        "1 unexplained\n    C4 tail: measured 2, paper 1.5")
    with pytest.raises(ValueError, match="explained='typo'"):
        classify(ClaimRow("C4", "tail", "2", "1.5", False, explained="typo"))
    later = ClaimRow("C14", "sign changes", "38 of N=100", "two clusters", False,
                     explained="later stage")
    assert classify(later) == "paper: later stage"
    summary = verdict_summary([later])
    assert "1 explained, our figure's run ends before the stage" in summary
    assert "where the paper is wrong" not in summary  # our run's limit, not the paper's
