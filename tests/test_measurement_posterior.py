"""The sampled Bayesian posterior of a model updating (issue 47, point 4: "or a Bayesian posterior by
sampling where asked").

References: a Gaussian density (the Laplace approximation exact) and a one-disk drivetrain on a
ground spring, whose only natural frequency f = sqrt(k/J)/2π gives the posterior of ln k in closed
form up to a one-dimensional quadrature; the shipped tap test of examples/measured (its true mount
values known from make_data.py); generalised Pareto draws of known shape for the tail fit.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

import mechdyn
from mechdyn.drivetrain import Disk, Drivetrain, GroundDamper, GroundSpring
from mechdyn.measurement import identify_modes, read_uff, update_model
from mechdyn.measurement.identify import IdentifiedModes, StabilisationChart
from mechdyn.measurement.posterior import PosteriorWarning, _gpd_fit, pareto_smooth, sample_posterior
from mechdyn.measurement.updating import UpdateError

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "measured"
INERTIA = 1.0  # kg·m², the disk
K_MODEL = 1.0e4  # N·m/rad, the model file's ground spring
K_TRUE = 1.3e4  # N·m/rad, the "machine's"
SPRING = "ground_springs.g.stiffness"
MAP = {"p0": "d0"}


def _sdof(k: float = K_MODEL) -> Drivetrain:
    return Drivetrain([Disk("d0", INERTIA)], [GroundSpring("g", "d0", k), GroundDamper("c", "d0", 1.0)])


def _measured(scatter: float) -> IdentifiedModes:
    """The one mode of the true machine, measured without error, with a relative frequency scatter."""
    w = np.array([np.sqrt(K_TRUE / INERTIA)])
    e = np.zeros(0)
    return IdentifiedModes(
        omega=w,
        damping=np.array([0.01]),
        shapes=np.ones((1, 1), complex),
        residues=np.zeros((1, 0, 1), complex),
        omega_scatter=scatter * w,
        damping_scatter=np.zeros(1),
        shape_scatter=np.zeros(1),
        stable_orders=np.zeros(1, int),
        outputs=(("p0", "rz"),),
        references=(),
        chart=StabilisationChart(e, e, e, np.zeros(0, int), None),  # type: ignore[arg-type]
    )


def _quadrature(scatter: float, prior: float) -> tuple[float, float]:
    """Posterior mean and standard deviation of ln k by quadrature: residual (f/f_meas − 1)/σ with
    f/f_meas = exp((θ − ln k_true)/2), prior (θ − ln k_model)/σ_prior (what update_model minimises)."""
    t = np.linspace(np.log(K_MODEL) - 12 * prior, np.log(K_MODEL) + 12 * prior, 400001)
    r = np.expm1((t - np.log(K_TRUE)) / 2) / np.hypot(scatter, 1e-6)
    lp = -0.5 * (r**2 + ((t - np.log(K_MODEL)) / prior) ** 2)
    p = np.exp(lp - lp.max())
    p /= p.sum()
    mean = float(p @ t)
    return mean, float(np.sqrt(p @ (t - mean) ** 2))


def _update(tmp_path, scatter, prior=1.0, **kw):
    path = mechdyn.save(_sdof(), tmp_path / "sdof.toml")
    return update_model(
        path,
        _measured(scatter),
        kw.pop("parameters", [SPRING]),
        MAP,
        prior_uncertainty=prior,
        model_error=1e-6,
        max_uncertainty=100.0,
        **kw,
    )


def test_sampled_gaussian_matches_its_mean_and_covariance():
    # a Gaussian in ln p: the Laplace approximation is exact, the sample must agree within its error
    rng = np.random.default_rng(4)
    A = rng.standard_normal((3, 3))
    C = A @ A.T + 3 * np.eye(3)
    mu = rng.standard_normal(3)
    Ci = np.linalg.inv(C)
    post = sample_posterior(lambda t: -0.5 * (t - mu) @ Ci @ (t - mu), mu, C, 2000, seed=1)
    assert post.valid and post.stages == 1 and post.pareto_k < 0.5
    assert np.all(np.abs(post.mean_log - mu) < 4 * post.mcse_log)
    sd = np.sqrt(np.diag(C))
    np.testing.assert_allclose(post.std_log, sd, rtol=4 / np.sqrt(2 * post.ess))
    R = C / np.outer(sd, sd)
    np.testing.assert_allclose(post.correlation, R, atol=4 / np.sqrt(post.ess))
    z = stats.norm.ppf(0.975)
    lo, hi = np.log(post.interval_95).T
    np.testing.assert_allclose(lo, mu - z * sd, atol=0.15 * np.max(sd))
    np.testing.assert_allclose(hi, mu + z * sd, atol=0.15 * np.max(sd))


@pytest.mark.parametrize("shape", [-0.2, 0.3, 0.8])
def test_tail_shape_of_generalised_pareto_draws_recovered(shape):
    x = np.sort(stats.genpareto(c=shape, scale=2.0).rvs(20000, random_state=np.random.default_rng(1)))
    k, sigma = _gpd_fit(x)
    assert abs(k - shape) < 0.05 and abs(sigma / 2.0 - 1) < 0.05
    # the weights of a Pareto tail of shape 0.8: k̂ says so; bounded weights: k̂ below 0.5
    heavy = np.log(stats.genpareto(c=0.8).rvs(4000, random_state=np.random.default_rng(2)))
    assert pareto_smooth(heavy)[1] > 0.7
    assert pareto_smooth(np.log(np.random.default_rng(3).uniform(0.5, 1.0, 4000)))[1] < 0.5


def test_single_stiffness_posterior_agrees_with_the_linear_covariance(tmp_path):
    # 1 % frequency scatter: the posterior of ln k is Gaussian to well within the sampling error
    lin = _update(tmp_path, 0.01)
    up = _update(tmp_path, 0.01, posterior="sampling", samples=400)
    post = up.posterior
    assert post.valid and post.stages == 1
    assert abs(post.mean_log[0] - np.log(lin.value[0])) < 4 * post.mcse_log[0]
    assert abs(up.log_std[0] / lin.log_std[0] - 1) < 4 / np.sqrt(2 * post.ess)
    mean, sd = _quadrature(0.01, 1.0)
    assert abs(post.mean_log[0] - mean) < 4 * post.mcse_log[0]
    assert abs(up.log_std[0] / sd - 1) < 4 / np.sqrt(2 * post.ess)
    # the updated value (the file written) is the optimum either way; the interval is the sample's
    assert up.value[0] == lin.value[0]
    np.testing.assert_allclose(up.interval_95[0], post.interval_95[0])
    s = up.summary()
    assert s["posterior_method"].startswith("sampling")
    assert lin.summary()["posterior_method"].startswith("linear")
    entry = s[SPRING]
    assert entry["interval_95"][0] < entry["posterior_median"] < entry["interval_95"][1]
    assert s["posterior"]["valid"] and "the diagnostics pass" in s["posterior"]["statement"]
    assert {"posterior_mean", "posterior_median"} <= set(up.to_frame().columns)


def test_non_gaussian_posterior_matches_the_quadrature_where_the_linear_one_does_not(tmp_path):
    # 30 % scatter and a vague prior: f/f_meas − 1 ≥ −1 floors the likelihood, a long left tail
    up = _update(tmp_path, 0.3, prior=5.0, posterior="sampling", samples=400)
    post = up.posterior
    mean, sd = _quadrature(0.3, 5.0)
    assert post.valid
    assert abs(post.mean_log[0] - mean) < 4 * post.mcse_log[0]
    assert abs(post.std_log[0] / sd - 1) < 0.2
    # the Laplace approximation at the optimum is 40 % too narrow here
    assert np.sqrt(post.laplace_covariance_log[0, 0]) < 0.7 * sd


def test_tap_test_credible_intervals_contain_the_true_values():
    found = identify_modes(read_uff(EXAMPLE / "tap_test.uff"), f_min_hz=3.0, f_max_hz=28.0)
    points = dict(mechdyn.load(EXAMPLE / "tap_test.toml").model.mapping)
    paths = [f"mounts.*.{q}.{d}" for q in ("stiffness", "damping") for d in "xyz"]
    truth = np.array([0.6e6, 0.7e6, 2.3e6, 600.0, 700.0, 2300.0])  # make_data.py: N/m, N·s/m
    up = update_model(
        EXAMPLE / "machine.toml",
        found,
        paths,
        points,
        damping_error=0.05,
        starts=0,
        posterior="sampling",
        samples=200,
    )
    assert up.posterior.valid and up.identifiable.all()
    lo, hi = up.interval_95.T
    assert np.all((lo <= truth) & (truth <= hi)), np.column_stack([lo, truth, hi])
    assert up.posterior_samples.shape == (200, 6)
    s = up.summary()
    assert len(s["posterior_correlation"]["matrix"]) == 6
    assert s["mounts.*.stiffness.z"]["unit"] == "kN/m"  # the file's unit
    assert s["mounts.*.stiffness.z"]["interval_95"][0] < 2300.0 < s["mounts.*.stiffness.z"]["interval_95"][1]


def test_the_same_seed_gives_the_same_posterior(tmp_path):
    a = _update(tmp_path, 0.01, posterior="sampling", samples=200, seed=5).posterior
    b = _update(tmp_path, 0.01, posterior="sampling", samples=200, seed=5).posterior
    c = _update(tmp_path, 0.01, posterior="sampling", samples=200, seed=6).posterior
    np.testing.assert_array_equal(a.samples_log, b.samples_log)
    np.testing.assert_array_equal(a.weights, b.weights)
    assert not np.array_equal(a.samples_log, c.samples_log)


def test_a_degenerate_sample_is_flagged(tmp_path):
    # too few draws for the interval's ends
    with pytest.warns(PosteriorWarning, match="effective sample size"):
        up = _update(tmp_path, 0.01, posterior="sampling", samples=50)
    assert not up.posterior.valid
    assert "NOT a valid sample" in up.summary()["posterior"]["statement"]
    # a proposal far narrower than the posterior, not allowed to adapt: the weights' tail says so
    with pytest.warns(PosteriorWarning, match="Pareto"):
        post = sample_posterior(lambda t: -0.5 * t @ t / 25.0, np.zeros(3), np.eye(3), 1000, adapt=0)
    assert post.pareto_k > post.pareto_k_threshold and not post.valid


def test_an_unidentifiable_parameter_is_not_sampled(tmp_path):
    # the damper does not move the undamped mode: zero sensitivity, held at its prior, not sampled
    up = _update(
        tmp_path, 0.01, parameters=[SPRING, "ground_dampers.c.damping"], posterior="sampling", samples=200
    )
    assert list(up.identifiable) == [True, False]
    assert up.posterior.names == (SPRING,)
    assert up.prior[1] == 1.0 and np.all(up.posterior_samples[:, 1] == 1.0)
    note = up.summary()["ground_dampers.c.damping"]["note"]
    assert "not identifiable" in note and "not sampled" in note


def test_predictions_resample_the_posterior(tmp_path):
    up = _update(tmp_path, 0.01, posterior="sampling", samples=400)
    space = up.input_space()
    assert [v.name for v in space.variables] == ["posterior_draw"]
    # stratified resampling reproduces the weighted mean
    u = (np.arange(4000) + 0.5) / 4000
    np.testing.assert_allclose(
        np.mean(np.log(up.posterior_draw(u)[:, 0])), up.posterior.mean_log[0], atol=1e-3
    )

    def frequency(loaded):
        from mechdyn.drivetrain.modal import modal

        return [float(modal(loaded.model).omega[0]) / (2 * np.pi)]

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        band = up.predict(frequency, ["frequency_Hz"], 64, seed=2)
    median = band.distributions[0].quantiles[0.5].value
    f_median = np.sqrt(up.posterior.median[0] / INERTIA) / (2 * np.pi)
    sd = f_median * up.log_std[0] / 2  # f ∝ sqrt(k)
    assert abs(median - f_median) < 4 * 1.25 * sd / np.sqrt(64)


def test_bad_posterior_settings_are_named(tmp_path):
    with pytest.raises(UpdateError, match="posterior='mcmc'"):
        _update(tmp_path, 0.01, posterior="mcmc")
    with pytest.raises(UpdateError, match="samples=10"):
        _update(tmp_path, 0.01, posterior="sampling", samples=10)


def test_a_measurement_file_asks_for_the_sampled_posterior_and_the_table_says_so(tmp_path, capsys):
    """``posterior = "sampling"`` in ``[updating]``: modes-from-test samples the posterior; its summary
    names the method and the values table's note gives the sample's own validity statement."""
    import json
    import shutil

    from mechdyn.cli.main import main

    folder = tmp_path / "measured"
    shutil.copytree(Path(__file__).resolve().parents[1] / "examples" / "measured", folder)
    path = folder / "tap_test.toml"
    text = path.read_text()
    head, _, _ = text.partition("\n[predict]")  # the band is another test's; the posterior is this one's
    path.write_text(
        head.replace("damping_error = 0.05", 'damping_error = 0.05\nposterior = "sampling"\nsamples = 200')
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PosteriorWarning)
        main(
            [
                "modes-from-test",
                str(path),
                "--bootstrap",
                "0",
                "--starts",
                "0",
                "--db",
                str(tmp_path / "r.db"),
            ]
        )
    out, err = capsys.readouterr()
    assert "credible intervals of the sampled posterior" in out, err
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PosteriorWarning)
        main(
            [
                "modes-from-test",
                str(path),
                "--bootstrap",
                "0",
                "--starts",
                "0",
                "--json",
                "--db",
                str(tmp_path / "r.db"),
            ]
        )
    summary = json.loads(capsys.readouterr().out)
    assert summary["posterior_method"] == "sampling"
    assert summary["posterior_diagnostics"]["effective_sample_size"] > 0
    for entry in summary["updated_values"].values():
        if entry["identifiable"]:
            mean, low, high = (
                next(v for k, v in entry.items() if k.startswith(p))
                for p in ("posterior_mean", "low_95", "high_95")
            )
            assert low <= mean <= high
