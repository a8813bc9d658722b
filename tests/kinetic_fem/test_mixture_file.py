"""A mixture from a TOML file (kinetic_fem.mixture_file) and ``kinetic-fem mixture``."""

import pytest

from kinetic_fem.cli import main
from kinetic_fem.mixture_file import mixture_from_table, read_mixture
from kinetic_fem.mixture_solve import solve_mixture
from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution

GOOD = """[mixture]
masses = [1.0, 4.0]
fractions = [0.5, 0.5]
alpha = [[0.9, 0.8], [0.8, 0.7]]
forcing = "same_power"
diffusion = 2.0
density = 0.5
"""


def test_read_mixture_and_the_command(tmp_path, capsys):
    path = tmp_path / "mix.toml"
    path.write_text(GOOD)
    mix, density = read_mixture(path)
    assert mix.masses == (1.0, 4.0) and density == 0.5
    assert mix.diffusions().tolist() == [2.0, 0.5]
    assert mix.constant_alpha().tolist() == [[0.9, 0.8], [0.8, 0.7]]
    assert main(["mixture", str(path), "--method", "gaussian", "--quiet"]) == 0
    ratio = solve_mixture(mix, density=density, method="gaussian").temperature_ratio()
    assert f"T_1/T_2 = {ratio:.8g}" in capsys.readouterr().out


def test_baths_and_cooling_tables():
    mix, _ = mixture_from_table({"masses": [1, 2], "fractions": [0.25, 0.75],
                                 "forcing": "baths",
                                 "baths": [{"friction": 1.0, "diffusion": 1.0},
                                           {"friction": 2.0, "diffusion": 0.5}]})
    assert mix.frictions().tolist() == [1.0, 2.0]
    mix, _ = mixture_from_table({"masses": [1, 2], "fractions": [0.25, 0.75],
                                 "forcing": "cooling"})
    assert not mix.heated


@pytest.mark.parametrize(("table", "named"), [
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.6]}, "sum to 1"),
    ({"masses": [1.0, 0.0], "fractions": [0.5, 0.5]}, r"masses\[1\]"),
    ({"masses": [1.0, 2.0], "fractions": [1.5, -0.5]}, r"fractions\[1\]"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "alpha": [[0.9, 0.8], [0.7, 0.9]]},
     "symmetric"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "mass": 3}, r"unknown key\(s\) \['mass'\]"),
    ({"masses": [1.0, 2.0]}, r"missing key\(s\) \['fractions'\]"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "forcing": "hot"}, "forcing"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "diffusion": -1.0}, "diffusion"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "density": "x"}, "density"),
    ({"masses": [1.0, 2.0], "fractions": [0.5, 0.5], "forcing": "baths",
      "baths": [{"friction": 1.0}]}, r"baths\[0\]"),
])
def test_bad_tables_name_the_key(table, named):
    with pytest.raises(ValueError, match=named) as info:
        mixture_from_table(table)
    assert str(info.value).startswith("[mixture]")


def test_a_method_that_cannot_do_the_mixture_is_a_clear_cli_error(tmp_path, capsys):
    path = tmp_path / "mix.toml"
    path.write_text(GOOD)
    with pytest.raises(SystemExit) as info:
        main(["mixture", str(path), "--method", "maxwell", "--quiet"])
    assert info.value.code == 2
    assert "Maxwell kernel" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text("[mix]\nmasses = [1, 2]\n")
    with pytest.raises(SystemExit):
        main(["mixture", str(bad)])
    assert "[mixture]" in capsys.readouterr().err


def test_restitution_laws_in_a_mixture_file(tmp_path, capsys):
    """Laws as strings, alone or in the alpha table: the DSMC, the FEM and the first-order
    Sonine heated states run them; the Sonine Galerkin series names what it cannot do; a
    malformed law names the key and the forms."""
    path = tmp_path / "laws.toml"
    path.write_text('[mixture]\nmasses = [1.0, 3.0]\nfractions = [0.5, 0.5]\n'
                    'alpha = [[0.8, "viscoelastic:0.1"], ["viscoelastic:0.1", '
                    '"threshold:0.6:0.5"]]\n')
    mix, _ = read_mixture(path)
    assert mix.laws[0][1] == ViscoelasticRestitution(0.1)
    assert mix.laws[1][1] == ThresholdRestitution(0.6, 0.5)
    assert main(["mixture", str(path), "--method", "dsmc", "-N", "200", "--collisions",
                 "40", "--seed", "1", "--quiet"]) == 0
    assert "T_1/T_2" in capsys.readouterr().out
    for method in ("fem", "sonine", "gaussian"):
        assert main(["mixture", str(path), "--method", method, "--quiet"]) == 0
        assert "T_1/T_2" in capsys.readouterr().out
    with pytest.raises(SystemExit) as info:
        main(["mixture", str(path), "--method", "spectral", "--quiet"])
    assert info.value.code == 2
    assert "constant restitution coefficient" in capsys.readouterr().err
    with pytest.raises(ValueError, match=r"alpha: .*threshold:ALPHA:SPEED"):
        mixture_from_table({"masses": [1, 2], "fractions": [0.5, 0.5],
                            "alpha": "threshold:0.6"})
