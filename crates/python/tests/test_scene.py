"""Scenes from Python: from a file or a dict, checked as `musclefem check` checks them,
run into a `Result` whose history, frames and VTU files are those of `musclefem run`."""

import filecmp
import subprocess
import sys
import types

import numpy as np
import pytest

import musclefem

from helpers import CLI, CUBE, box_deck, cube_dict

needs_cli = pytest.mark.skipif(not CLI.exists(), reason="needs target/release/musclefem")


def test_from_toml_is_the_scene_file_and_check_says_what_the_command_prints():
    scene = musclefem.Scene.from_toml(str(CUBE))
    report = scene.check()
    assert report.startswith(f"{CUBE}: ok\n")
    assert report.endswith(scene.describe())
    assert scene.toml == CUBE.read_text()
    if CLI.exists():
        printed = subprocess.run(
            [str(CLI), "check", str(CUBE)], check=True, capture_output=True, text=True
        ).stdout
        assert report == printed


def test_a_dict_scene_runs_as_its_file():
    from_file = musclefem.Scene(str(CUBE)).run()
    from_dict = musclefem.Scene.from_dict(cube_dict()).run()
    assert list(from_dict) == list(from_file)
    for column in from_file:
        np.testing.assert_array_equal(from_dict[column], from_file[column], err_msg=column)
    assert musclefem.Scene.from_dict(cube_dict()).check().startswith("Scene.from_dict: ok\n")


def test_a_bad_dict_names_its_key():
    scene = cube_dict()
    scene["materials"][0]["model"] = "neo-hooke"
    with pytest.raises(
        musclefem.MusclefemError,
        match=r"^Scene\.from_dict: materials\[0\]\.model: unknown material model 'neo-hooke' "
        r"\(did you mean `neo-hookean`\?\)",
    ):
        musclefem.Scene.from_dict(scene)
    scene = cube_dict()
    scene["parts"][0]["mesh"]["sise"] = [0.01] * 3
    with pytest.raises(musclefem.MusclefemError, match=r"parts\[0\]\.mesh\.sise: unknown field"):
        musclefem.Scene.from_dict(scene)
    scene = cube_dict()
    del scene["parts"][0]["name"]
    with pytest.raises(musclefem.MusclefemError, match=r"parts\[0\]: missing field `name`"):
        musclefem.Scene.from_dict(scene)
    scene = cube_dict()
    scene["step"]["duration"] = None
    with pytest.raises(musclefem.MusclefemError, match=r"step\.duration: None has no TOML value"):
        musclefem.Scene.from_dict(scene)
    scene = cube_dict()
    scene["step"]["duration"] = object()
    with pytest.raises(musclefem.MusclefemError, match=r"step\.duration: a object has no TOML"):
        musclefem.Scene.from_dict(scene)


def test_a_dict_scene_finds_its_mesh_file_in_its_base_directory(tmp_path):
    box_deck(tmp_path / "box.inp")
    scene = {
        "schema_version": 1,
        "materials": [{"name": "rubber", "model": "neo-hookean", "parameters": {"mu": 1e4}}],
        "parts": [
            {
                "name": "box",
                "material": "rubber",
                "element": "hex8-fbar",
                "density": 1000.0,
                "mesh": {"file": "box.inp"},
            }
        ],
        "displacements": [
            {"part": "box", "nodes": "ORIGIN", "components": ["x", "y", "z"]},
            {"part": "box", "nodes": "INSERTION", "components": ["z"], "value": 0.003},
        ],
        "step": {"solver": "implicit", "duration": 1.0, "output_interval": 0.5,
                 "implicit": {"increments": 2}},
    }
    described = musclefem.Scene.from_dict(scene, base_dir=tmp_path).describe()
    assert "24" in described and "part 'box'" in described
    # Elsewhere the file is not found, and the error names the key that named it.
    with pytest.raises(musclefem.MusclefemError, match=r"parts\[0\]\.mesh"):
        musclefem.Scene.from_dict(scene, base_dir=tmp_path / "elsewhere")
    # NumPy values and path objects are written as TOML values too.
    scene["parts"][0]["mesh"]["file"] = tmp_path / "box.inp"
    scene["step"]["duration"] = np.float64(1.0)
    scene["step"]["implicit"]["increments"] = np.int64(2)
    scene["displacements"][1]["components"] = np.array(["z"])
    result = musclefem.Scene.from_dict(scene, base_dir=tmp_path).run()
    assert result["time_s"][-1] == 1.0 and len(result["time_s"]) == 2


def test_check_refuses_a_body_free_to_move():
    scene = cube_dict()
    scene["displacements"] = scene["displacements"][:2]
    free = musclefem.Scene.from_dict(scene)
    with pytest.raises(musclefem.MusclefemError, match="Scene.from_dict"):
        free.check()
    with pytest.raises(musclefem.MusclefemError, match="Scene.from_dict"):
        free.run()


def test_the_result_holds_the_history_frames_and_mesh_as_arrays():
    result = musclefem.Scene(str(CUBE)).run()
    assert isinstance(result, musclefem.Result)
    assert set(result.history) == set(result) and "time_s" in result
    np.testing.assert_array_equal(result.history["time_s"], result["time_s"])
    assert result.get("no such column") is None
    with pytest.raises(KeyError):
        result["no such column"]
    assert result.steps == 10
    # A frame every 0.1 s from the start: 11, as the command line writes.
    frames = result.frames
    assert len(frames) == 11
    assert [f["time_s"] for f in frames] == pytest.approx(np.linspace(0, 1, 11), abs=1e-12)
    last = frames[-1]
    assert last["displacement"].shape == (125, 3) and last["displacement"].dtype == np.float64
    assert last["cauchy_stress"].shape == (64, 6) and last["von_mises"].shape == (64,)
    assert last["fiber_stretch"].shape == (64,)
    # Homogeneous uniaxial stress: every element carries sigma_xx = F / a, the von Mises
    # stress is sigma_xx, and the face x1 has moved 5 mm.
    force = result["reaction_cube.x1.x_n"][-1]
    area = (0.01 + last["displacement"][:, 1].min()) * (0.01 + last["displacement"][:, 2].min())
    np.testing.assert_allclose(last["cauchy_stress"][:, 0], force / area, rtol=1e-9)
    np.testing.assert_allclose(last["von_mises"], force / area, rtol=1e-9)
    assert last["displacement"][:, 0].max() == pytest.approx(0.005, rel=1e-12)
    mesh = result.mesh
    assert mesh["points"].shape == (125, 3) and mesh["blocks"] == ["cube"]
    assert mesh["fiber_direction_reference"].shape == (64, 3)
    assert musclefem.Scene(str(CUBE)).run(keep_frames=False).frames == []


@needs_cli
def test_write_vtu_writes_the_command_lines_files_byte_for_byte(tmp_path):
    result = musclefem.Scene(str(CUBE)).run()
    result.write_vtu(str(tmp_path / "py"))
    subprocess.run(
        [str(CLI), "run", str(CUBE), "--out", str(tmp_path / "cli")], check=True, capture_output=True
    )
    names = ["history.csv", "result.pvd", "scene.toml"]
    names += [f"frames/frame_{k:05}.vtu" for k in range(11)]
    for name in names:
        assert filecmp.cmp(tmp_path / "py" / name, tmp_path / "cli" / name, shallow=False), name
    with pytest.raises(musclefem.MusclefemError, match="already holds results"):
        result.write_vtu(str(tmp_path / "py"))
    result.write_vtu(str(tmp_path / "py"), force=True)
    # A run into a directory keeps the same frames in memory.
    written = musclefem.Scene(str(CUBE)).run(out=str(tmp_path / "out"))
    for kept, computed in zip(written.frames, result.frames):
        for name, values in computed.items():
            np.testing.assert_array_equal(kept[name], values, err_msg=name)


def test_the_history_as_a_data_frame_or_a_clear_message_without_pandas(monkeypatch):
    result = musclefem.Scene(str(CUBE)).run()
    try:
        import pandas
    except ImportError:
        pass
    else:
        table = result.history_frame()
        assert isinstance(table, pandas.DataFrame)
        assert list(table.columns) == list(result)
        np.testing.assert_array_equal(table["time_s"].to_numpy(), result["time_s"])
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match=r"history_frame\(\) needs pandas"):
        result.history_frame()


def test_threads_give_the_same_numbers_and_zero_is_refused():
    scene = musclefem.Scene(str(CUBE))
    everywhere, one = scene.run(), scene.run(threads=1)
    for column in everywhere:
        np.testing.assert_array_equal(one[column], everywhere[column], err_msg=column)
    with pytest.raises(musclefem.MusclefemError, match="threads= 0: at least one thread"):
        scene.run(threads=0)
    with pytest.warns(UserWarning, match="more than the"):
        scene.run(threads=10_000)


def test_progress_is_off_by_default_and_lines_or_tqdm_when_asked(monkeypatch, capsys):
    scene = musclefem.Scene(str(CUBE))
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    scene.run()
    assert capsys.readouterr().err == ""
    scene.run(progress=True)
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].startswith("t = 0.000000e0 s of 1 s (0 %)")
    assert lines[-1].startswith("t = 1.000000e0 s of 1 s (100 %)")

    class FakeBar:
        made = []

        def __init__(self, total, unit, desc):
            self.total, self.shown, self.closed = total, 0.0, False
            FakeBar.made.append(self)

        def update(self, step):
            self.shown += step

        def close(self):
            self.closed = True

    package, auto = types.ModuleType("tqdm"), types.ModuleType("tqdm.auto")
    package.__path__, package.auto, auto.tqdm = [], auto, FakeBar
    monkeypatch.setitem(sys.modules, "tqdm", package)
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    scene.run(progress=True)
    (bar,) = FakeBar.made
    assert bar.total == 1.0 and bar.shown == pytest.approx(1.0) and bar.closed
