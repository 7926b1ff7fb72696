"""A new study is one package plus one registry line (docs/architecture.md, "How to add
a study"): the toy study in tests/toy_study/ is registered by adding its name to the
registry (and its package where ``studies.<name>`` is found), and then ``wallsim compare
toy``, ``wallsim keys toy``, the Python API and the error contract all work with no
other edit. Its numbers are Rankine's: K = (1 - sin 30) / (1 + sin 30) = 1/3."""

import json
import sys

import pytest

import cli
import studies.registry
import tests.toy_study as toy


@pytest.fixture
def registered(monkeypatch):
    """The registry line (NAMES + "toy") and the package at studies/toy."""
    monkeypatch.setattr(studies.registry, "NAMES", studies.registry.NAMES + ("toy",))
    monkeypatch.setattr("studies.NAMES", studies.registry.NAMES)
    monkeypatch.setitem(sys.modules, "studies.toy", toy)


def test_the_cli_runs_the_new_study(registered, tmp_path, capsys):
    assert cli.main(["compare", "toy", "--phi", "30", "--out", str(tmp_path), "--json", "--quiet"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["K"] == pytest.approx(1 / 3, rel=1e-12)                         # Rankine, phi 30
    assert result["thrust_kN_per_m"] == pytest.approx(0.5 / 3 * 18.0 * 3.0 ** 2, rel=1e-12)
    folder = next((tmp_path / "toy").iterdir())
    assert {"config.toml", "manifest.json", "result.json", "profile.csv"} <= {p.name for p in folder.iterdir()}
    assert "phi_deg = 30" in (folder / "config.toml").read_text()


def test_keys_the_api_and_bad_input_work_unchanged(registered, tmp_path, capsys):
    assert cli.main(["keys", "toy"]) == 0
    assert "phi_deg" in capsys.readouterr().out
    s = studies.get("toy")
    r = s.run(s.case(phi_deg=40.0, H=2.0), out=str(tmp_path))
    assert r["K"] == pytest.approx(0.21744283205399, rel=1e-10)                 # (1 - sin 40) / (1 + sin 40)
    assert cli.main(["compare", "toy", "--phi", "95", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "phi" in err and "Traceback" not in err
