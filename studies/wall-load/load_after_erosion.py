"""How much of the load lands where the wall under it has already eroded? (issue 11, a diagnosis)

The wall stage puts each deposition record on its face cell's original front-face nodes
(:mod:`impactdyn.wall._load`); after the elements under a cell erode, later records land on the
corners of the surviving rim, not on the crater's floor, and after a whole column erodes, on nodes
of no element.  For a finished Whipple run this reruns its wall stage up to the last arrival with
frames every ``--every`` µs, finds when each front-layer element and each element column first
eroded, and prints the share of the deposited impulse (by magnitude) that arrived on a cell after
its front element had eroded, and after its whole column had, with the hourglass share at the
last arrival.  Nothing is written.

    python studies/wall-load/load_after_erosion.py RUN_FOLDER [--every 0.25]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from impactdyn.debris import read_deposition
from impactdyn.wall import run_wall
from impactdyn.whipple import load_whipple_case


def first_eroded(times: np.ndarray, eroded: np.ndarray) -> np.ndarray:
    """Per column of ``eroded`` (frames × items), the first frame time it is True, else inf."""
    return np.where(eroded.any(axis=0), times[np.argmax(eroded, axis=0)], np.inf)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path)
    ap.add_argument("--every", type=float, default=0.25, help="frame interval, µs")
    args = ap.parse_args()
    case = load_whipple_case(args.run / "case.toml")
    grid, deposition, _ = read_deposition(args.run / "debris" / "debris.h5")
    last = float(deposition.time.max())
    options = case.wall_options.replaced(output_interval_us=args.every,
                                                                       max_time_us=last + 1.0)
    result = run_wall(grid, deposition, case.wall.material, options)
    nx, ny, nz = result.mesh.shape
    if (nx, nz) != (grid.shape[0], grid.shape[2]):
        raise SystemExit("the wall is refined in the plane: records and element columns differ")
    times = np.array([f.time for f in result.frames])
    eroded = np.array([f.eroded.reshape(ny, nx * nz) for f in result.frames])     # layer j, then i + nx k
    front = first_eroded(times, eroded[:, 0, :])
    column = first_eroded(times, eroded.all(axis=1))
    size = np.linalg.norm(deposition.impulse, axis=1)
    cell = deposition.element
    print(f"{args.run.name}: {cell.size} records, last arrival {last:.2f} µs, "
          f"{np.isfinite(front).sum()} front-layer elements eroded by then")
    print(f"impulse arriving after its cell's front element eroded: {size[deposition.time > front[cell]].sum() / size.sum():.4f}")
    print(f"impulse arriving after its cell's whole column eroded:  {size[deposition.time > column[cell]].sum() / size.sum():.4f}")
    print(f"verdict at {result.measures['end_time_us']:.2f} µs: {result.verdict}; "
          f"hourglass / internal {result.measures['hourglass_to_internal']:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
