"""The FEM states of a granular mixture (kinetic_fem.solvers.fem.mixture).

Checks that could fail: a mixture of identical species is the one-species FEM solution
on the same mesh to round-off (constant coefficients and restitution laws); the inelastic
Maxwell mixture against its closed moment equations (kinetic_fem.solvers.maxwell_mixture);
laws per pair against the DSMC; the public entry and bad input.
"""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.mixture_state import MixtureState
from kinetic_fem.model import (
    ThresholdRestitution,
    UnsupportedModelError,
    ViscoelasticRestitution,
)
from kinetic_fem.solvers import maxwell_mixture
from kinetic_fem.solvers.fem import mixture as fem_mixture
from kinetic_fem.solvers.fem.grading import graded_vertices


@pytest.mark.parametrize("gamma", [1.0, 0.5])
def test_identical_species_are_the_one_species_solution(gamma):
    """Equal masses and alphas: the coupled system is the one-species discretisation term
    for term (the loss split half outer, half inner), so on one mesh T, a2 and f agree to
    round-off (measured 1e-15 in T, 3e-14 in f)."""
    verts = 1.4 * graded_vertices(12.0, 0.4, grading=0.0)  # sqrt(T) about 1.4
    with pytest.warns(ResolutionWarning):
        one = kf.solve_heated(0.7, kernel=gamma, vertices=verts, order=2)
    mix = kf.Mixture.white_noise((2.0, 2.0), (0.3, 0.7), alpha=0.7, kernel=gamma)
    with pytest.warns(ResolutionWarning):
        state = kf.solve_heated(mix, vertices=verts, order=2)
    assert isinstance(state, MixtureState)
    np.testing.assert_allclose(state.temperatures / 2.0, one.temperature, rtol=1e-13)
    np.testing.assert_allclose(state.a2, one.a2, rtol=0, atol=1e-13)
    for dist in state.distributions:
        np.testing.assert_allclose(dist.values, one.values, rtol=2e-13)


@pytest.mark.parametrize("law", [ViscoelasticRestitution(0.1), ThresholdRestitution(0.6, 0.5)])
@pytest.mark.parametrize("gamma", [1.0, 0.5])
def test_identical_species_with_a_law_are_the_one_species_solution(law, gamma):
    """Velocity-dependent laws (the pair rule at each pair's |g|): identical species are
    the one-species FEM state with that law on the same mesh to round-off (measured: T
    9e-16, a2 7e-16, f 3e-14)."""
    verts = 1.8 * graded_vertices(12.0, 0.4, grading=0.0)
    with pytest.warns(ResolutionWarning):
        one = kf.solve_heated(law, kernel=gamma, vertices=verts, order=2)
    mix = kf.Mixture.white_noise((2.0, 2.0), (0.3, 0.7), alpha=law, kernel=gamma)
    with pytest.warns(ResolutionWarning):
        state = kf.solve_heated(mix, vertices=verts, order=2)
    np.testing.assert_allclose(state.temperatures / 2.0, one.temperature, rtol=1e-13)
    np.testing.assert_allclose(state.a2, one.a2, rtol=0, atol=1e-13)
    for dist in state.distributions:
        np.testing.assert_allclose(dist.values, one.values, rtol=2e-13)


def test_laws_per_pair_with_unequal_masses_agree_with_the_dsmc():
    """Masses 1:10, a viscoelastic law, a constant and a threshold law in one table: the
    default FEM state against the mixture DSMC (T_s and a2_s, |z| < 4; measured over seeds
    1-16: mean z within 0.13 of 0, standard deviations 1.0-1.2; seeds 1-4 of four more
    law mixtures |z| <= 3.1, ``benchmarks/results/fem_mixture_laws.md``)."""
    from particles.dsmc_mixture import simulate_mixture

    mix = kf.Mixture.white_noise((1.0, 10.0), (0.3, 0.7), alpha=[
        [ViscoelasticRestitution(0.1), 0.8], [0.8, ThresholdRestitution(0.5, 1.0)]])
    state = kf.solve_heated(mix)
    run = simulate_mixture(mix, 2000, seed=1, collisions_per_particle=300, relax=30)
    assert np.all(np.abs(run.temperatures - state.temperatures) < 4 * run.temperature_errors)
    assert np.all(np.abs(run.a2 - state.a2) < 4 * run.a2_errors)


@pytest.mark.slow   # 8 s
def test_mixture_with_a_law_converges_at_the_order_of_the_element():
    """Viscoelastic law, masses 1:3: T_s and a2_s against spacing 0.0625 converge at the
    observed orders 3.9 (P2) and 5.8-5.9 (P3) (spacing 0.5 -> 0.125)."""
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1))
    ref = kf.solve_heated(mix, order=3, spacing=0.0625)
    for order, expected in ((2, 3.9), (3, 5.8)):
        errors = []
        for spacing in (0.5, 0.25, 0.125):
            state = kf.solve_heated(mix, order=order, spacing=spacing)
            errors.append(float(np.max(np.abs(state.temperatures / ref.temperatures - 1.0))))
        rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
        assert np.all(np.abs(rates - expected) < 0.3), rates


@pytest.mark.parametrize("convention", ["same_diffusion", "same_power"])
def test_maxwell_mixture_heated_matches_the_exact_moments(convention):
    """Kernel 0, unequal masses, fractions and alphas: T_s and a2_s against the exact
    moment equations (measured at P3, spacing 0.5: T 6e-11, a2 6e-8; spacing 0.25:
    2e-13 and 1.1e-9)."""
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.3, 0.7), alpha=[[0.5, 0.7], [0.7, 0.9]],
                                 kernel=0.0, convention=convention)
    exact = maxwell_mixture.steady_state(mix)
    state = kf.solve_heated(mix, method="fem", spacing=0.5)
    np.testing.assert_allclose(state.temperatures, exact.temperatures, rtol=2e-10)
    np.testing.assert_allclose(state.a2, exact.a2, rtol=0, atol=2e-7)
    assert state.temperature_ratio() == pytest.approx(exact.temperature_ratio(), rel=4e-10)
    assert state.zeta is None and state.info.converged


def test_bad_input_is_named():
    heated = kf.Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=0.8)
    cooling = kf.Mixture((1.0, 2.0), (0.5, 0.5), alpha=0.8)
    with pytest.raises(ValueError, match="kernel=0.5 does not apply to a Mixture"):
        kf.solve_heated(heated, kernel=0.5)
    with pytest.raises(ValueError, match="forced species"):
        kf.solve_heated(cooling)
    with pytest.raises(ValueError, match="without forcing"):
        kf.solve_cooling(heated)
    law = kf.Mixture((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1))
    with pytest.raises(UnsupportedModelError, match="constant restitution.*no scaling state"):
        kf.solve_cooling(law)
    # delta 0.5: the law holds up to g = 6.29, the meshes reach g = 63
    wide = kf.Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.5))
    with pytest.raises(ValueError, match=r"relative speeds up to 6.29.*FEM meshes of species"):
        kf.solve_heated(wide)
    saturating = kf.Mixture((1.0, 2.0), (0.5, 0.5), alpha=0.8,
                            kernel=kf.SaturatingKernel(1.0))
    with pytest.raises(UnsupportedModelError, match="homogeneous kernel"):
        kf.solve_cooling(saturating)
    with pytest.raises(ValueError, match="unknown mixture-heated method 'fd'"):
        kf.solve_heated(heated, method="fd")
    with pytest.raises(ValueError, match="one per species"):
        fem_mixture.solve_mixture_heated(heated, vertices=[np.linspace(-5, 5, 11)] * 3)


@pytest.mark.slow
def test_identical_species_cool_as_one_species():
    """Free cooling of identical species (hard rods, alpha 0.5): zeta and a2 of the
    one-species HCS (0.43556748, 0.1610182; measured at spacing 0.5: 1e-8, 3e-7).
    Slow: 5.6 s here, most of it the one-species cooling solves."""
    mix = kf.Mixture((1.0, 1.0), (0.3, 0.7), alpha=0.5)
    state = kf.solve_cooling(mix, spacing=0.5)
    one = kf.solve_cooling(0.5)
    assert state.zeta == pytest.approx(one.info.extra["zeta"], rel=5e-8)
    np.testing.assert_allclose(state.temperatures, 1.0, rtol=1e-12)
    np.testing.assert_allclose(state.a2, one.a2, rtol=0, atol=1e-6)


@pytest.mark.slow
def test_maxwell_mixture_cooling_matches_the_exact_ratio():
    """Kernel 0: the temperature ratio and the cooling rate against the largest
    eigenvalue of the exact second-moment equations (the c^-4 tails are truncated at
    the cut-off: measured 7e-8 and 1e-6 at spacing 0.5)."""
    mix = kf.Mixture((1.0, 3.0), (0.3, 0.7), alpha=[[0.5, 0.7], [0.7, 0.9]], kernel=0.0)
    exact = maxwell_mixture.cooling_state(mix)
    with pytest.warns(ResolutionWarning):
        state = kf.solve_cooling(mix, spacing=0.5)
    assert state.temperature_ratio() == pytest.approx(exact.temperature_ratio(), rel=2e-7)
    assert state.zeta == pytest.approx(exact.zeta, rel=3e-6)


def test_maxwell_mixture_cooling_coarse_matches_the_exact_ratio():
    """The default-run check of the cooling state: kernel 0, m 1:3, x 0.3/0.7, an alpha
    table, on the coarse P3 mesh (spacing 1.0, 145 dofs a species): the temperature
    ratio and the cooling rate against the exact second-moment equations (measured
    1.3e-7 and 1.2e-7, the truncated c^-4 tails; 2 s)."""
    mix = kf.Mixture((1.0, 3.0), (0.3, 0.7), alpha=[[0.5, 0.7], [0.7, 0.9]], kernel=0.0)
    exact = maxwell_mixture.cooling_state(mix)
    with pytest.warns(ResolutionWarning):
        state = kf.solve_cooling(mix, spacing=1.0)
    assert state.info.converged
    assert state.temperature_ratio() == pytest.approx(exact.temperature_ratio(), rel=3e-7)
    assert state.zeta == pytest.approx(exact.zeta, rel=3e-7)
    temperature = sum(x * t for x, t in zip(mix.fractions, state.temperatures, strict=True))
    assert temperature == pytest.approx(1.0, rel=1e-12)


@pytest.mark.slow
def test_hard_rods_1_to_3_cooling_state_converges_in_the_mesh():
    """Hard rods, m 1:3, x 0.5/0.5, alpha 0.7 (not found at spacing 0.5 before issue 27's
    last round): the default mesh (spacing 0.25) and the halved one agree on the
    temperature ratio and the cooling rate (measured 7e-11 and 8e-11; T1/T2 =
    0.7447600907, zeta = 0.2123161875), and first-order Sonine is off by about 1 %
    (0.7361). Slow: 4.6 s."""
    mix = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=0.7)
    coarse = kf.solve_cooling(mix)
    fine = kf.solve_cooling(mix, spacing=0.125)
    assert coarse.temperature_ratio() == pytest.approx(fine.temperature_ratio(), rel=1e-9)
    assert coarse.zeta == pytest.approx(fine.zeta, rel=1e-9)
    assert fine.temperature_ratio() == pytest.approx(0.7447600907, rel=1e-9)
    assert fine.zeta == pytest.approx(0.2123161875, rel=1e-9)


def test_failed_heated_newton_restarts_on_trimmed_meshes(caplog):
    """When the heated Newton fails on the default meshes, the meshes are cut where the
    iterate's f_s sigma_s falls below TRIM_LEVEL (1e-33) and Newton restarts from it.
    Hard rods m 1:2, alpha 0.8 at spacing 0.5: both starts failed before (the Gaussian's
    at residual 9e-16 with steps 3e-3 after 40 iterations: the near-null edge modes);
    the trimmed restart converges in 9 steps, and T1/T2 agrees with spacing 0.125
    (0.8082591066) to the discretisation error (measured 1.6e-8; 2.6 s)."""
    mix = kf.Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=0.8)
    with caplog.at_level("INFO", logger=fem_mixture.__name__):
        state = kf.solve_heated(mix, spacing=0.5)
    assert "cut-offs trimmed" in caplog.text
    assert state.info.converged
    assert state.temperature_ratio() == pytest.approx(0.8082591066, rel=3e-8)
    np.testing.assert_allclose(state.a2, [-0.0240493, 0.0012614], rtol=0, atol=1e-6)


@pytest.mark.slow
def test_light_species_cooling_state_is_found_on_the_first_meshes(caplog):
    """Hard rods m 1:10, alpha 0.5 (free cooling): the default cut-offs were 36 thermal
    velocities (33 decades of the start plus 2 thermal velocities, f_s sigma_s ~ 1e-46 at
    the light species' edge), where Newton reached a residual of 4e-17 with steps stuck at
    3e-4 and only the trimmed restart converged (25 s); at 38 decades of the start Newton
    converges on the first meshes (1 s).  Checked against an explicit cut-off of 30
    (measured differences 7.7e-12 in T1/T2, 6e-12 in zeta before) and the finer spacing
    0.2 (5.4e-11 and 1.0e-10: the discretisation error)."""
    mix = kf.Mixture((1.0, 10.0), (0.5, 0.5), alpha=0.5)
    with caplog.at_level("INFO", logger=fem_mixture.__name__):
        state = kf.solve_cooling(mix)
    assert "cut-offs trimmed" not in caplog.text
    assert "widening" not in caplog.text
    assert state.info.converged
    explicit = kf.solve_cooling(mix, cutoff=30.0)
    assert state.temperature_ratio() == pytest.approx(explicit.temperature_ratio(), rel=5e-11)
    assert state.zeta == pytest.approx(explicit.zeta, rel=5e-11)
    assert state.temperature_ratio() == pytest.approx(0.2289312706, rel=1e-9)
    assert state.zeta == pytest.approx(0.1499123381, rel=1e-9)


@pytest.mark.slow
def test_same_power_light_species_heated_state_is_found():
    """same_power (D_s = 1/m_s), m2/m1 = 0.1, x 0.5/0.5, alpha 0.9, hard rods: Newton on
    the default meshes (cut-offs 14 thermal velocities, f_s sigma_s ~ 1e-63 at the light
    species' edge) does not converge (steps 0.3 at residual 5e-15 after 40 iterations);
    the trimmed restart does, and agrees with an explicit cut-off of 13 thermal velocities
    (measured: T1/T2 1.3246784853 both, difference 2.5e-13; 9 s) and with spacing 0.125
    (1.32467848530, 2e-11; before the light species' finer mesh, ``species_spacing``,
    the default gave 1.3246784883, 2.3e-9 off)."""
    mix = kf.Mixture.white_noise((1.0, 0.1), (0.5, 0.5), alpha=0.9, convention="same_power")
    state = kf.solve_heated(mix)
    assert state.info.converged
    explicit = kf.solve_heated(mix, cutoff=13.0)
    assert state.temperature_ratio() == pytest.approx(explicit.temperature_ratio(), rel=1e-9)
    assert state.temperature_ratio() == pytest.approx(1.3246784853, rel=1e-9)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("gamma", [1.0, 0.5])
def test_self_pairs_by_the_one_species_kernel_equal_the_cross_kernel(order, gamma):
    """The pairs of a species with itself, summed by the one-species P2/P3 kernel
    (``self_collision``), equal the two-mesh kernel with one mesh twice (residual,
    Jacobian and loss moment; measured 2e-15, 2e-15 and 8e-15 relative)."""
    from kinetic_fem.operators.fem_pair_mixture import cross_collision, self_collision

    mix = kf.Mixture.white_noise((1.0, 3.0), (0.3, 0.7), alpha=[[0.6, 0.7], [0.7, 0.8]],
                                 kernel=gamma)
    var = fem_mixture.gaussian_variances(mix, 1.0, False)
    verts = fem_mixture.mixture_meshes(mix, var, [8.0 * np.sqrt(v) for v in var], spacing=0.6)
    md = fem_mixture.MixtureDiscretisation(mix, verts, 1.3, order)
    ref_x, ref_w = md.discs[0].basis.quadrature
    ref_x = np.ascontiguousarray(ref_x[0])
    for s, (disc, v) in enumerate(zip(md.discs, var, strict=True)):
        u = -0.5 * disc.dof_locations**2 / v - 0.05 * np.abs(disc.dof_locations) ** 3
        verts_s, dofs_s = disc.mesh_arrays
        xq, wq, eq = disc.points
        a, b = md.rules[s, s]
        w = md.density * mix.fractions[s]
        r_o, r_i, jxo, joi, jxi, jii, loss = cross_collision(
            verts_s, dofs_s, u, xq, wq, eq, verts_s, dofs_s, u, order, ref_x, ref_w,
            float(a), float(b), md._kernel_argument, w, 0.5 * w, 0.5 * w, True, True)
        res, jac, fast_loss = self_collision(
            verts_s, dofs_s, u, xq, wq, eq, ref_x, ref_w, float(mix.constant_alpha()[s, s]),
            w, md._kernel_argument, True)
        full = jxo.T + joi + jxi.T + jii
        assert np.max(np.abs(res - r_o - r_i)) < 1e-13 * np.max(np.abs(res))
        assert np.max(np.abs(jac - full)) < 1e-13 * np.max(np.abs(jac))
        assert fast_loss == pytest.approx(loss, rel=1e-13)


def test_near_elastic_cooling_mixture_needs_no_trimmed_restart(caplog):
    """Identical hard rods at alpha 0.9 (the start's tail falls 10 e-folds per thermal
    velocity): the default cut-offs end 5 decades past the start's 33 (not 2 thermal
    velocities, 9 decades, where Newton stagnated for 40 iterations before the trimmed
    restart, 8 s), Newton converges at once, and zeta is the one-species one (measured
    8.6e-11 relative: the cut-offs at 11.4 against 13.5 thermal velocities)."""
    mix = kf.Mixture((1.0, 1.0), (0.5, 0.5), alpha=0.9)
    with caplog.at_level("INFO", logger="kinetic_fem.solvers.fem.mixture"):
        state = kf.solve_cooling(mix)
    assert not [r for r in caplog.records if "Newton failed" in r.getMessage()]
    one = kf.solve_cooling(0.9, order=3, spacing=0.25)
    assert state.zeta == pytest.approx(one.info.extra["zeta"], rel=1e-9)


def test_cooling_mixture_meshes_are_graded_like_one_species(caplog):
    """Hard rods m 1:10 at alpha 0.5: the cooling meshes grade the tail as the one-species
    HCS meshes do (367 dofs per species against 343 for one species; the heated grading
    gave 445), Newton converges on the first meshes (the near-null modes of the coarser
    tail stay below the monitored f > 1e-15), and the ratio is the one of the finer
    tail grading within its discretisation error (measured 3e-11; spacing 0.125: 4e-11)."""
    mix = kf.Mixture((1.0, 10.0), (0.5, 0.5), alpha=0.5)
    with caplog.at_level("INFO", logger="kinetic_fem.solvers.fem.mixture"):
        state = kf.solve_cooling(mix)
    assert not [r for r in caplog.records if "Newton failed" in r.getMessage()
                or "widening" in r.getMessage()]
    one = kf.solve_cooling(0.5, order=3, spacing=0.25)
    assert max(state.info.extra["n_dofs"]) <= 1.1 * one.info.extra["n_dofs"]
    heated_grading = fem_mixture.mixture_meshes(
        mix, [1.0, 1.0], [30.0, 30.0], spacing=0.25)
    cooling_grading = fem_mixture.mixture_meshes(
        mix, [1.0, 1.0], [30.0, 30.0], spacing=0.25, cooling=True)
    assert cooling_grading[0].size < heated_grading[0].size
    assert state.temperature_ratio() == pytest.approx(0.2289312705819, rel=1e-9)


def test_one_species_start_is_solved_once_per_restitution_coefficient():
    """A sweep over masses at one alpha solves the one-species start once (kept by
    ``START_CACHE``), and a state from the kept start is the state from a fresh one bit
    for bit (the start is read, never changed)."""
    fem_mixture._one_species_heated.cache_clear()
    first = kf.solve_heated(kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.6),
                            spacing=0.4)
    second = kf.solve_heated(kf.Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=0.6),
                             spacing=0.4)
    info = fem_mixture._one_species_heated.cache_info()
    assert (info.misses, info.hits) == (1, 1)
    again = kf.solve_heated(kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.6),
                            spacing=0.4)
    fem_mixture._one_species_heated.cache_clear()
    fresh = kf.solve_heated(kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.6),
                            spacing=0.4)
    assert np.array_equal(again.temperatures, fresh.temperatures)
    assert np.array_equal(again.temperatures, first.temperatures)
    assert second.temperature_ratio() != first.temperature_ratio()


def test_heated_chord_steps_in_p_give_the_plain_newton_state(monkeypatch):
    """The heated Newton's chord steps in P (``HEATED_CHORD_LEVEL``) and the loose
    one-species start (``START_TOL``) end at the state of plain Newton from the fully
    converged start: T_s and a2_s equal to the Newton tolerance (1e-11; measured 3e-16),
    with no more Jacobians (alpha 0.7, m 1:1, spacing 0.4: two instead of four)."""
    mix = kf.Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.7)
    fem_mixture._one_species_heated.cache_clear()
    fast = kf.solve_heated(mix, spacing=0.4)
    monkeypatch.setattr(fem_mixture, "HEATED_CHORD_LEVEL", 0.0)
    monkeypatch.setattr(fem_mixture, "START_TOL", 1e-11)
    fem_mixture._one_species_heated.cache_clear()
    plain = kf.solve_heated(mix, spacing=0.4)
    fem_mixture._one_species_heated.cache_clear()
    np.testing.assert_allclose(fast.temperatures, plain.temperatures, rtol=1e-11, atol=0)
    np.testing.assert_allclose(fast.a2, plain.a2, rtol=0, atol=1e-11)

    def jacobians(state: MixtureState) -> int:
        return int(state.info.message.rsplit(";", 1)[1].split()[0])

    assert jacobians(fast) <= jacobians(plain)


def test_the_wide_species_mesh_is_finer_so_m_1_10_is_as_accurate_as_one_species():
    """At one spacing in thermal velocities the light (wide) species of masses 1:10 set
    the error (T_s 1.2e-9, a2_s 3.1e-9 at spacing 0.25 against 2e-10 for one species);
    with ``species_spacing`` its spacing is (sigma_min/sigma)^0.8 finer: measured against
    spacing 0.125, T_s 2.2e-11 relative and a2_s 6.0e-11 absolute (2 x 0.6 s).  Equal
    thermal velocities keep one spacing (identical species: the one-species state)."""
    sig = np.array([1.0, 2.0])
    assert fem_mixture.species_spacing(1.0, sig) == 1.0
    assert fem_mixture.species_spacing(2.0, sig) == pytest.approx(0.5**0.8, rel=1e-15)
    assert fem_mixture.species_spacing(1.5, np.array([1.5, 1.5])) == 1.0
    mix = kf.Mixture.white_noise((1.0, 10.0), (0.5, 0.5), alpha=0.9)
    state = kf.solve_heated(mix)
    fine = kf.solve_heated(mix, spacing=0.125)
    assert np.allclose(state.temperatures, fine.temperatures, rtol=5e-11, atol=0)
    assert np.allclose(state.a2, fine.a2, rtol=0, atol=1.2e-10)
    sizes = [len(d.values) for d in state.distributions]
    assert sizes[0] > 1.8 * sizes[1]   # the light species' mesh: 624 points against 320


def test_merged_rule_cuts_the_outer_elements_at_the_inner_vertices():
    """The cut rule: points inside their outer element, the pieces' lengths summing to
    the mesh, polynomials of the reference rule's degree integrated exactly on every
    outer element, and the element rule itself when the cuts are the outer vertices."""
    ref_x, ref_w = np.polynomial.legendre.leggauss(4)
    ref_x, ref_w = 0.5 * (ref_x + 1.0), 0.5 * ref_w
    outer = np.array([-3.0, -1.0, 0.0, 0.5, 2.0, 4.0])
    inner = np.array([-2.5, -1.0 + 1e-14, 0.2, 0.3, 3.0, 9.0])
    x, w, e = fem_mixture.merged_rule(outer, inner, ref_x, ref_w)
    assert np.all((x > outer[e]) & (x < outer[e + 1]))
    assert w.sum() == pytest.approx(7.0, rel=1e-15)
    # -2.5, 0.2, 0.3 and 3.0 cut elements (-1 + 1e-14 is the vertex -1, 9 is off the mesh)
    assert x.size == 4 * (outer.size - 1 + 4)
    for el in range(outer.size - 1):
        on = e == el
        lo, hi = outer[el], outer[el + 1]
        assert np.sum(w[on] * x[on] ** 7) == pytest.approx((hi**8 - lo**8) / 8, rel=1e-13)
    same = fem_mixture.merged_rule(outer, outer, ref_x, ref_w)
    plain = fem_mixture.merged_rule(outer, np.array([]), ref_x, ref_w)
    for a, b in zip(same, plain, strict=True):
        np.testing.assert_array_equal(a, b)


def test_identical_species_on_two_meshes_cool_as_one_species():
    """Identical species (hard rods, alpha 0.5) on meshes of bulk spacings 0.25 and 0.3:
    with the cut outer rule the cooling state is the one-species one to the
    discretisation's error (measured 4.2e-10 at most in T_s, a2_s and zeta against
    spacing 0.1; the element rule erred 4.1e-9, order 4, benchmarks/
    convergence_fem_mixture_cooling.py).  Bound: 1e-9, against one species at spacing
    0.15 (error 2e-12)."""
    mix = kf.Mixture((1.0, 1.0), (0.5, 0.5), alpha=0.5)
    variances = fem_mixture.gaussian_variances(mix, 1.0, True)
    cuts = [38.394] * 2
    meshes = [fem_mixture.mixture_meshes(mix, variances, cuts, spacing=h, cooling=True)[0]
              for h in (0.25, 0.3)]
    state = kf.solve_cooling(mix, vertices=meshes)
    one = kf.solve_cooling(0.5, order=3, spacing=0.15)
    zeta = float(one.info.extra["zeta"])
    assert state.zeta == pytest.approx(zeta, rel=1e-9)
    np.testing.assert_allclose(state.a2, [one.a2] * 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(state.temperatures, [1.0, 1.0], rtol=1e-9)
