"""No leak over 1000 submits: resident memory stays flat over 1000 frames submitted through the
binding (the engine rejects them after the binding has done all its work, so the map does not
grow), 1000 submits that raise, and 1000 reads of the results."""
import numpy as np

import ldsm


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def test_no_leak_over_1000_submits(scene):
    d = ldsm.open_dataset(str(scene))
    system = ldsm.System(None, d.calibration)  # threaded: frames go through the frame pool
    system.on_event(lambda e: None)
    flat = np.full((d.height, d.width), 90, np.uint8)
    wrong = np.zeros((8, 8), np.uint8)
    t = 0.0

    def round_trip(n):
        nonlocal t
        for _ in range(n):
            t += 0.01
            system.submit(flat, t, None)
            try:
                system.submit(wrong, t)
            except ldsm.InputError:
                pass
            system.trajectory()
            system.stats()

    round_trip(200)  # warm-up: pools, caches, the allocator
    system.finish()
    before = rss_mb()
    round_trip(1000)
    system.finish()
    after = rss_mb()
    assert system.stats()["submitted_frames"] == 1200
    # One leaked frame copy per submit would be 1000 * width * height bytes (hundreds of MB).
    assert after - before < 4.0, f"resident memory grew {after - before:.1f} MB"
