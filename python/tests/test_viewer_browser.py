"""The browser viewer in a real browser: `ldsm run --serve` on a short synthetic replay, the page opened in headless Chromium (driven over the DevTools pipe), waited on until
poses, points and an image have arrived (the page's window.ldsmViewer.counts), and a screenshot saved that
shows the trajectory; then `ldsm view` on the run's outputs the same way. Skips where Chromium is
absent."""
import json
import os
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

from cdp_pipe import Browser, find_chromium
from conftest import ldsm_exe

COUNTS = "JSON.stringify(window.ldsmViewer ? window.ldsmViewer.counts : null)"


def start_server(args):
    """Starts an ldsm command that serves the viewer at 127.0.0.1:0 and returns (process, url)."""
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + 60
    seen = []
    while time.monotonic() < end:
        line = proc.stderr.readline()
        if not line:
            break
        seen.append(line)
        m = re.search(r"viewer: (http://127\.0\.0\.1:\d+/)", line)
        if m:
            return proc, m.group(1)
    proc.kill()
    raise AssertionError("no viewer URL from ldsm:\n" + "".join(seen))


def wait_for_counts(browser, url, condition, limit=90):
    browser.open(url)
    end = time.monotonic() + limit
    counts = None
    while time.monotonic() < end:
        value = browser.evaluate(COUNTS)
        counts = json.loads(value) if value else None
        if counts and condition(counts):
            return counts
        time.sleep(0.5)
    raise AssertionError(f"the page did not get there in {limit} s: {counts}")


def trajectory_pixels(png):
    """Pixels of the trajectory's colour (#4fc3f7) in a screenshot, or None without matplotlib."""
    try:
        import matplotlib.image
    except ImportError:
        return None
    import numpy as np
    img = matplotlib.image.imread(png)[:, :-380, :3]  # the 3D view, not the panel's legend
    target = np.array([0x4F, 0xC3, 0xF7]) / 255.0
    return int((np.abs(img - target).max(axis=2) < 0.12).sum())


@pytest.fixture(scope="module")
def browser():
    chromium = find_chromium()
    if chromium is None:
        pytest.skip("Chromium not found (Debian: apt-get install chromium): browser test skipped")
    b = Browser(chromium)
    yield b
    b.close()


def test_live_run_and_finished_run_in_the_browser(browser, scene, scratch):
    out = scratch / "viewer_run"
    shot_dir = Path(os.environ.get("LDSM_TEST_TMP", str(scratch))) / "viewer_browser"
    shot_dir.mkdir(parents=True, exist_ok=True)
    # The threaded offline pipeline (the replay of --realtime drops frames when tracking is behind,
    # and a busy test machine would leave too few): every frame is tracked, live to the page.
    run, url = start_server([ldsm_exe(), "run", "--dataset", str(scene), "--serve", "127.0.0.1:0", "--serve-wait", "--out", str(out),
                             "--no-eval"])
    try:
        counts = wait_for_counts(browser, url, lambda c: c["poses"] >= 10 and c["points"] >= 100
                                 and c["images"] > 0 and c["drawn"] > 0)
        time.sleep(1.0)  # a few more frames drawn
        browser.screenshot(str(shot_dir / "live.png"))
        assert counts["rejected"] == 0 and counts["errors"] == 0, counts
        # The run is not disturbed by the page: it finishes, then serves until SIGINT.
        wait_for_counts(browser, url, lambda c: c["finished"], limit=120)
        time.sleep(1.0)  # drawn again, the whole run in view
        browser.screenshot(str(shot_dir / "finished.png"))
    finally:
        run.send_signal(signal.SIGINT)
        stdout, _ = run.communicate(timeout=60)
    assert run.returncode == 0, stdout
    assert "finished:" in stdout, stdout
    pixels = trajectory_pixels(str(shot_dir / "finished.png"))
    assert pixels is None or pixels > 50, f"{pixels} trajectory pixels in the screenshot"

    view, url = start_server([ldsm_exe(), "view", str(out), "--serve", "127.0.0.1:0",
                              "--seconds", "120"])
    try:
        counts = wait_for_counts(browser, url, lambda c: c["poses"] >= 10 and c["points"] > 100
                                 and c["keyframes"] >= 2 and c["drawn"] > 0)
        browser.screenshot(str(shot_dir / "view.png"))
        assert counts["finished"] and counts["errors"] == 0, counts
        pixels = trajectory_pixels(str(shot_dir / "view.png"))
        assert pixels is None or pixels > 50, f"{pixels} trajectory pixels in the screenshot"
    finally:
        view.send_signal(signal.SIGINT)
        view.communicate(timeout=30)
    assert view.returncode == 0
    if os.environ.get("LDSM_VIEWER_SCREENSHOT"):
        shutil.copy(shot_dir / "finished.png", os.environ["LDSM_VIEWER_SCREENSHOT"])
