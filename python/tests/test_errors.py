"""Bad input raises Python exceptions carrying ldsm's messages."""
import numpy as np
import pytest

import ldsm


@pytest.fixture(scope="module")
def system(scene):
    dataset = ldsm.open_dataset(str(scene))
    return ldsm.System({"system": {"deterministic": True}}, dataset.calibration), dataset


def test_frames_of_the_wrong_kind(system):
    s, d = system
    with pytest.raises(ldsm.InputError, match="uint8 array of shape"):
        s.submit(np.zeros((d.height, d.width), np.float32), 0.0)
    with pytest.raises(ldsm.InputError, match="uint8 array of shape"):
        s.submit(np.zeros((d.height, d.width, 3), np.uint8), 0.0)
    with pytest.raises(ldsm.InputError, match="uint8 array"):
        s.submit([[1, 2], [3, 4]], 0.0)
    with pytest.raises(ldsm.InputError, match="but the camera is"):
        s.submit(np.zeros((10, 12), np.uint8), 0.0)
    assert issubclass(ldsm.InputError, ldsm.Error) and issubclass(ldsm.Error, RuntimeError)
    # Strided views are fine (copied), and a flat frame is only rejected by the engine, counted.
    big = np.full((d.height, 2 * d.width), 100, np.uint8)
    s.submit(big[:, ::2], 1.0)
    assert s.stats()["rejected_frames"] == 1


def test_bad_configuration_names_the_key(scene):
    d = ldsm.open_dataset(str(scene))
    with pytest.raises(ldsm.ConfigError, match="no_such_key"):
        ldsm.System({"system": {"no_such_key": 1}}, d.calibration)
    with pytest.raises(ldsm.ConfigError, match="frame_pool_size"):
        ldsm.System({"system": {"frame_pool_size": 1}}, d.calibration)
    with pytest.raises(ldsm.ConfigError):
        ldsm.Config(42)
    c = ldsm.Config({"loop": {"enabled": False}})
    assert not c.loop_closure and "loop" in c.to_yaml()


def test_bad_files_and_arguments(scratch):
    with pytest.raises(ldsm.InputError):
        ldsm.open_dataset(str(scratch / "no_such_dataset"))
    with pytest.raises(ldsm.InputError):
        ldsm.load_calibration(str(scratch / "no_such_camera.txt"))
    with pytest.raises(ldsm.InputError, match=r"\(N, 8\)"):
        ldsm.ate(np.zeros((5, 3)), np.zeros((5, 8)))
    with pytest.raises(ldsm.InputError, match="need at least 3"):
        ldsm.ate(np.tile([0, 0, 0, 0, 0, 0, 0, 1.0], (2, 1)), np.tile([0, 0, 0, 0, 0, 0, 0, 1.0],
                                                                        (2, 1)))
    with pytest.raises(ldsm.ConfigError, match="align"):
        ldsm.ate(np.zeros((5, 8)), np.zeros((5, 8)), align="affine")
    with pytest.raises(ldsm.ConfigError, match="unknown level"):
        ldsm.set_log_level("loud")


def test_callback_must_be_callable(system):
    s, _ = system
    with pytest.raises(ldsm.InputError, match="callable"):
        s.on_event(5)
    s.on_event(None)
