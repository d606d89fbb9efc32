"""`import musclefem`: the materials, a material point, a scene and the elongation test
from Python, checked against closed forms and against the command line's files. The
scene's constructors, check, Result, frames and progress are in test_scene.py."""

import csv
import subprocess

import numpy as np
import pytest

import musclefem

from helpers import CLI, CUBE, box_deck, neo_hookean_uniaxial


def test_the_materials_list_their_parameters_with_units():
    materials = {m["name"]: m for m in musclefem.materials()}
    assert {"hill", "neo-hookean", "tendon"} <= set(materials)
    sigma0 = next(p for p in materials["hill"]["parameters"] if p["name"] == "sigma0")
    assert sigma0["unit"] == "Pa" and sigma0["default"] == 7e5
    assert sigma0["lower"] == 0.0


def test_a_neo_hookean_point_follows_the_closed_form():
    mu, d = 1e4, 2e-5
    result = musclefem.MaterialPoint("neo-hookean", mu=mu, D=d).uniaxial(
        [0.0, 1.0], [1.0, 1.5], dt=0.01
    )
    assert set(result) == {
        "time_s",
        "stretch",
        "engineering_stress_pa",
        "cauchy_stress_pa",
        "volume_ratio",
    }
    assert isinstance(result["stretch"], np.ndarray)
    for stretch, stress in zip(result["stretch"][1:], result["engineering_stress_pa"][1:]):
        expected = neo_hookean_uniaxial(mu, d, stretch)
        assert stress == pytest.approx(expected, rel=1e-6), stretch


def test_bad_input_raises_the_command_lines_message():
    with pytest.raises(musclefem.MusclefemError, match="sigma0"):
        musclefem.MaterialPoint("hill", sigma0=-1.0)
    with pytest.raises(musclefem.MusclefemError, match="no material|unknown"):
        musclefem.MaterialPoint("steel")
    point = musclefem.MaterialPoint("hill", n2=1.0)
    with pytest.raises(musclefem.MusclefemError, match="one stretch per time"):
        point.uniaxial([0.0, 1.0], [1.0])


def test_a_scene_runs_in_memory_and_into_a_run_directory_as_the_command_line(tmp_path):
    scene = musclefem.Scene(str(CUBE))
    assert "part 'cube'" in scene.describe()
    history = scene.run()
    assert history["time_s"][-1] == 1.0
    # The cube's end force against the closed form of the compressible neo-Hookean law.
    force = history["reaction_cube.x1.x_n"][-1]
    assert force == pytest.approx(neo_hookean_uniaxial(1e4, 2e-5, 1.5) * 1e-4, rel=1e-9)

    written = scene.run(out=str(tmp_path / "run"))
    for column, values in history.items():
        np.testing.assert_array_equal(values, written[column], err_msg=column)
    assert (tmp_path / "run" / "result.pvd").is_file()
    assert not (tmp_path / "run" / "checkpoint.bin").exists()
    # The same numbers as `musclefem run` writes, to the last digit.
    cli = tmp_path / "cli"
    if CLI.exists():
        subprocess.run([str(CLI), "run", str(CUBE), "--out", str(cli)], check=True)
        with open(cli / "history.csv") as table:
            rows = list(csv.DictReader(table))
        np.testing.assert_array_equal(
            [float(r["reaction_cube.x1.x_n"]) for r in rows], history["reaction_cube.x1.x_n"]
        )
    # An earlier run is not replaced without force.
    with pytest.raises(musclefem.MusclefemError, match="already holds results"):
        scene.run(out=str(tmp_path / "run"))


def test_a_bad_scene_names_its_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(CUBE.read_text().replace('model = "neo-hookean"', 'model = "neo-hooke"'))
    with pytest.raises(musclefem.MusclefemError, match=r"bad\.toml:16:9: unknown material model"):
        musclefem.Scene(str(bad))


def test_the_elongation_curve_is_the_command_lines(tmp_path):
    options = dict(shape="cylinder", grips="sliding", mesh_size=8.75, time_step=0.2)
    curve = musclefem.elongate("passive", **options)
    assert curve["engineering_strain"][-1] == pytest.approx(0.2, abs=1e-12)
    assert 0 < curve["stress_10pct_pa"] < curve["stress_20pct_pa"]
    with pytest.raises(musclefem.MusclefemError, match="grips 'glued'"):
        musclefem.elongate("passive", grips="glued")
    if CLI.exists():
        args = ["--shape", "cylinder", "--grips", "sliding", "--mesh-size", "8.75"]
        args += ["--time-step", "0.2", "--mode", "passive", "--out", str(tmp_path / "e")]
        subprocess.run([str(CLI), "elongate", *args], check=True, capture_output=True)
        with open(tmp_path / "e" / "curve.csv") as table:
            rows = list(csv.DictReader(table))
        np.testing.assert_array_equal(
            [float(r["engineering_stress_pa"]) for r in rows], curve["engineering_stress_pa"]
        )


def test_ctrl_c_stops_a_run_whose_directory_then_resumes_to_the_same_history(tmp_path):
    """Ctrl-C (SIGINT) in a Python process running a long scene: KeyboardInterrupt, the
    run directory holds complete frames and a checkpoint, and run(resume=True) in a new
    process finishes with the history of a run never stopped."""
    import signal
    import sys
    import time

    long = tmp_path / "long.toml"
    long.write_text(
        CUBE.read_text()
        .replace("divisions = [4, 4, 4]", "divisions = [8, 8, 8]")
        .replace("increments = 10 }", "increments = 400 }")
        .replace("output_interval = 0.1", "output_interval = 0.01")
    )
    # Python's own Ctrl-C handler, as in an interactive interpreter: a process started in
    # the background of a non-interactive shell (a CI script's `cmd &`) inherits SIGINT
    # ignored, and Python then leaves it ignored.
    script = (
        "import signal, sys, musclefem\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "scene = musclefem.Scene(sys.argv[1])\n"
        "try:\n"
        "    scene.run(out=sys.argv[2], resume=sys.argv[3] == 'resume')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted'); sys.exit(130)\n"
        "print('complete')\n"
    )
    run = [sys.executable, "-c", script, str(long), str(tmp_path / "cut")]
    child = subprocess.Popen(run + ["start"], stdout=subprocess.PIPE, text=True)
    started = time.time()
    while not (tmp_path / "cut" / "checkpoint.bin").exists():
        assert time.time() - started < 120, "no checkpoint after 2 min"
        assert child.poll() is None, "the run ended before it could be stopped"
        time.sleep(0.05)
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=120)
    assert child.returncode == 130 and "interrupted" in out, (child.returncode, out)
    assert (tmp_path / "cut" / "checkpoint.bin").is_file()

    resumed = subprocess.run(run + ["resume"], capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0 and "complete" in resumed.stdout, resumed.stderr
    whole = musclefem.Scene(str(long)).run(out=str(tmp_path / "whole"))
    for name in ["history.csv", "result.pvd"]:
        assert (tmp_path / "cut" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name
    assert len(whole["time_s"]) == 400


def test_fibers_of_a_box_run_from_origin_to_insertion(tmp_path):
    deck = tmp_path / "box.inp"
    box_deck(deck)
    field = musclefem.fibers(str(deck), ["ORIGIN"], ["INSERTION"])
    assert field["direction"].shape == (24, 3) and field["centroid"].shape == (24, 3)
    assert field["element"][0] == 101
    # A uniform flow along the box: every fiber along +z, the potential linear in z.
    np.testing.assert_allclose(field["direction"], np.tile([0.0, 0.0, 1.0], (24, 1)), atol=1e-8)
    np.testing.assert_allclose(field["potential"], 1 - field["centroid"][:, 2] / 0.03, atol=1e-8)
    assert field["inlet_flux"] == pytest.approx(field["outlet_flux"], rel=1e-8)
    with pytest.raises(musclefem.MusclefemError, match="NOWHERE"):
        musclefem.fibers(str(deck), ["NOWHERE"], ["INSERTION"])
