"""The same synthetic sequence through Python and through `ldsm run --deterministic` gives the
same trajectory, the same bytes in trajectory.txt; events reach the callback; evaluation works on the arrays."""
import subprocess

import numpy as np

import ldsm
from conftest import ldsm_exe

FRAMES = 60  # the whole `short` scene


def test_python_matches_the_cli(scene, scratch):
    out = scratch / "cli_run"
    subprocess.run([ldsm_exe(), "run", "--dataset", str(scene), "--deterministic", "--max-frames",
                    str(FRAMES), "--out", str(out), "--no-eval"], check=True, capture_output=True)
    cli = ldsm.read_trajectory(str(out / "trajectory.txt"))

    dataset = ldsm.open_dataset(str(scene))
    system = ldsm.System({"system": {"deterministic": True}}, dataset.calibration,
                         dataset.photometric)
    events = []
    system.on_event(events.append)
    for i, frame in enumerate(dataset):
        if i == FRAMES:
            break
        assert frame.image.dtype == np.uint8 and frame.image.shape == (dataset.height,
                                                                       dataset.width)
        system.submit(frame.image, frame.timestamp, frame.exposure_ms)
    system.finish()
    py = system.trajectory()

    # Through the same TUM writer as the CLI (shortest round-trip digits): the same bytes.
    ldsm.write_trajectory(str(scratch / "python_trajectory.txt"), py)
    assert (scratch / "python_trajectory.txt").read_bytes() == (out / "trajectory.txt").read_bytes()
    # And read back the same way (the reader renormalises quaternions): the same numbers.
    back = ldsm.read_trajectory(str(scratch / "python_trajectory.txt"))
    assert back.shape == cli.shape and back.shape[0] > 20
    assert np.array_equal(back, cli)
    assert np.abs(py - cli).max() < 1e-12
    kinds = [e["type"] for e in events]
    assert kinds.count("frame") == FRAMES
    assert kinds.count("initialized") == 1 and kinds.count("keyframe") > 0
    points = system.map_points()
    assert points.ndim == 2 and points.shape[1] == 4 and points.shape[0] > 100
    assert system.keyframe_trajectory().shape[1] == 8
    # Deterministic: the initializer had every frame until the map, none went without it.
    stats = system.stats()
    assert stats["initializer_frames"] > 1 and stats["initializer_busy_frames"] == 0


def test_calibration_refinement_in_stats(scene):
    # A window of three keyframes is full early: the refinement fuses a window estimate per
    # keyframe from then on, and stats() reports it and its history as SystemStats does.
    dataset = ldsm.open_dataset(str(scene))
    system = ldsm.System({"system": {"deterministic": True},
                          "window": {"min_keyframes": 2, "max_keyframes": 3}},
                         dataset.calibration, dataset.photometric)
    for frame in dataset:
        system.submit(frame.image, frame.timestamp, frame.exposure_ms)
    system.finish()
    cal = system.stats()["calibration"]
    assert cal["windows"] > 0 and len(cal["history"]) == min(cal["windows"], 256)
    windows = [h["windows"] for h in cal["history"]]
    assert windows == sorted(set(windows)) and windows[-1] == cal["windows"]
    assert cal["history"][-1]["radial_estimate"] == cal["radial_estimate"]
    assert cal["radial_sigma"] > 0
    # Never below the formal sigma (it scales it by the window overlap and the observed scatter).
    assert cal["realistic_radial_sigma"] >= cal["radial_sigma"]
    assert cal["history"][-1]["realistic_radial_sigma"] == cal["realistic_radial_sigma"]
    assert cal["configured"]["width"] > 0 and cal["applied"]["fx"] > 0


def test_evaluation_on_arrays(scene):
    dataset = ldsm.open_dataset(str(scene))
    gt = dataset.groundtruth()
    assert gt is not None and gt.shape[1] == 8
    # A copy moved by a similarity: ATE 0 after Sim(3) alignment.
    moved = gt.copy()
    moved[:, 1:4] = moved[:, 1:4] * 2.5 + np.array([1.0, -2.0, 0.5])
    r = ldsm.ate(gt, moved)
    assert r["rmse"] < 1e-6 and abs(r["scale"] - 1 / 2.5) < 1e-6
    assert r["matched"] == gt.shape[0]
    rpe = ldsm.rpe(gt, gt)
    assert rpe["segments"] > 0 and rpe["translation_percent"] < 1e-9
