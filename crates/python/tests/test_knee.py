"""`musclefem.knee`: `musclefem knee` from Python. The squat takes hours on the default
(Visible Human) knee and about 14 minutes on the procedural one (the command line's test
runs that, ignored by default), so these tests check only that its options are read and
refused as the command reads and refuses them, before any output."""

import pytest

import musclefem


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(duration=-1.0), r"--duration -1 s must be positive"),
        (dict(passive=True, active=True), r"cannot be used with"),
        (dict(element="tet4"), r"--element tet4: the Visible Human knee's muscles are meshed with tet10"),
        (
            dict(anatomy="procedural", element="tet4"),
            r"--element tet4: the knee's muscles are meshed with hex8",
        ),
        (dict(tolerance=0.0), r"--tolerance 0 must be a positive percentage"),
        (dict(tolerance=5.0, resolution="coarse"), r"cannot be used with"),
        (dict(frame_interval=-0.1), r"--frame-interval -0.1 s must be 0"),
        (dict(time_step=5.0), r"--time-step 5 s must be positive and below the duration"),
        (dict(resolution="huge"), r"invalid value 'huge' for '--resolution"),
        (dict(peak_flexion=120.0), r"--peak-flexion 120° must be from 5° to 90°"),
        (dict(resume=True, force=True), r"cannot be used with"),
    ],
)
def test_bad_options_are_refused_before_any_output(tmp_path, options, message):
    out = tmp_path / "out"
    with pytest.raises(musclefem.MusclefemError, match=message):
        musclefem.knee(out=str(out), **options)
    assert not out.exists()


def test_earlier_results_are_not_replaced_without_force(tmp_path):
    (tmp_path / "peak_stress.csv").write_text("earlier results\n")
    with pytest.raises(musclefem.MusclefemError, match=r"peak_stress\.csv exists: use --force"):
        musclefem.knee(out=str(tmp_path))
    assert (tmp_path / "peak_stress.csv").read_text() == "earlier results\n"


def test_an_anatomy_directory_without_muscles_is_named(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(musclefem.MusclefemError, match="neither muscles.msh nor muscles.inp"):
        musclefem.knee(anatomy=str(tmp_path / "empty"), out=str(tmp_path / "out"))


def test_a_completed_study_has_nothing_to_resume(tmp_path):
    (tmp_path / "peak_stress.csv").write_text("earlier results\n")
    with pytest.raises(musclefem.MusclefemError, match=r"completed, there is nothing to resume"):
        musclefem.knee(out=str(tmp_path), resume=True)
    assert (tmp_path / "peak_stress.csv").read_text() == "earlier results\n"


def test_nothing_is_written_when_there_is_no_checkpoint_to_resume(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(musclefem.MusclefemError, match=r"has no checkpoint to resume from"):
        musclefem.knee(out=str(out), resume=True)
    assert not out.exists()
