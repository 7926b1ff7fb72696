"""`wallsim calibrate cantilever`: the bonded-ball sheet pile of Sizkow & El Shamy at
model scale (E 40 GPa, t 5 mm, L 13.5 cm; docs/reference/seismic-sheetpile.md)
against Euler-Bernoulli through the study layer: run folder, JSON, numbers."""

import json

import pytest

import cli


@pytest.mark.slow
def test_calibrated_strip_bends_as_the_beam(tmp_path, capsys):
    assert cli.main(["calibrate", "cantilever", "--json", "--quiet", "--out", str(tmp_path)]) == 0
    r = json.loads(capsys.readouterr().out)
    # EI per width = E t^3 / 12 = 40e9 x 0.005^3 / 12 = 416.7 N m^2/m (the reference's model EI)
    assert r["bond"]["EI_per_width_N_m2_per_m"] == pytest.approx(40e9 * 0.005**3 / 12, rel=1e-12)
    # tip deflection F L^3 / (3 EI): the joints' midpoint rule errs by D^2 / (4 L^2) = 3.4e-4
    assert abs(r["tip_deflection_over_beam"] - 1.0) < 2e-3
    # first frequency 1.875^2 sqrt(EI / (m L^4)) / 2 pi: a beam of two ball sheets has
    # rotary inertia and shear that Euler-Bernoulli leaves out, so it vibrates lower
    assert 0.95 < r["frequency_over_beam"] < 1.0
    folder = tmp_path / "cantilever"
    run = next(p for p in folder.iterdir())
    assert {"config.toml", "manifest.json", "result.json"} <= {p.name for p in run.iterdir()}
