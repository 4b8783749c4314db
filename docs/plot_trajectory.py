#!/usr/bin/env python3
"""Runs ldsm on a dataset from Python and plots the estimated trajectory (top view) against the
ground truth, aligned by Sim(3), with matplotlib.

    PYTHONPATH=build/python /usr/bin/python3 docs/plot_trajectory.py DATASET [--out plot.png]

e.g. after `build/apps/ldsm sim --scene loop --out /tmp/loop`:
    PYTHONPATH=build/python /usr/bin/python3 docs/plot_trajectory.py /tmp/loop --max-frames 600
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no screen needed
import matplotlib.pyplot as plt  # noqa: E402

import ldsm  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dataset")
    ap.add_argument("--out", default="trajectory.png")
    ap.add_argument("--max-frames", type=int, default=0)
    ap.add_argument("--deterministic", action="store_true")
    args = ap.parse_args()

    dataset = ldsm.open_dataset(args.dataset)
    config = ldsm.Config()
    config.deterministic = args.deterministic
    system = ldsm.System(config, dataset.calibration, dataset.photometric)
    keyframes = []
    system.on_event(lambda e: keyframes.append(e["keyframe_id"]) if e["type"] == "keyframe"
                    else None)
    for i, frame in enumerate(dataset):
        if args.max_frames and i >= args.max_frames:
            break
        system.submit(frame.image, frame.timestamp, frame.exposure_ms)
    system.finish()
    est = system.trajectory()
    print(f"{est.shape[0]} poses, {len(keyframes)} keyframes, "
          f"{system.map_points().shape[0]} map points")

    fig, ax = plt.subplots(figsize=(6, 6))
    gt = dataset.groundtruth()
    if gt is not None and est.shape[0] >= 3:
        r = ldsm.ate(gt, est)
        print(f"ATE {r['rmse']:.4f} m over {r['matched']} poses")
        aligned = r["aligned_estimate"]
        ax.plot(gt[:, 1], gt[:, 3], "k--", lw=1, label="ground truth")
        ax.plot(aligned[:, 1], aligned[:, 3], "C0", lw=1.5,
                label=f"ldsm (ATE {r['rmse']:.3f} m)")
    else:
        ax.plot(est[:, 1], est[:, 3], "C0", lw=1.5, label="ldsm")
    ax.set_xlabel("x")
    ax.set_ylabel("z")
    ax.set_aspect("equal")
    ax.legend()
    fig.savefig(args.out, dpi=120, bbox_inches="tight")
    print(f"plot in {args.out}")


if __name__ == "__main__":
    main()
