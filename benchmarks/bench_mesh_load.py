"""Benchmark: ``MeshFoot.from_file`` on a binary STL of about a million facets (issue 43).

Writes a closed semi-sphere mesh of 8 n^2 facets (n = 354: 1,002,528 facets, 50 MB) as a
binary STL in a temporary directory, then loads it in a fresh process and reports the
wall time of ``MeshFoot.from_file`` and the process's peak resident memory above what it
held once numpy, trimesh and mudrft were imported (``resource.getrusage``: Linux/macOS).

Run ``python benchmarks/bench_mesh_load.py [--n N] [--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from mudrft.feet.meshgen import semisphere_mesh

#: The load, timed in a fresh process so that its peak memory is its own.
_CHILD = """
import json, resource, sys, time
import numpy, trimesh, mudrft.feet
scale = 1024 if sys.platform != "darwin" else 1  # ru_maxrss: KiB on Linux, bytes on macOS
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale
t0 = time.perf_counter()
foot = mudrft.feet.MeshFoot.from_file(sys.argv[1], unit="mm")
seconds = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale
print(json.dumps({"facets": len(foot), "seconds": seconds, "peak_bytes": peak - before}))
"""


def write_binary_stl(path: Path, triangles: np.ndarray) -> None:
    """A binary STL (80-byte header, uint32 count, 50-byte records) of ``triangles``."""
    record = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    rows = np.zeros(len(triangles), dtype=record)
    rows["v"] = triangles
    with open(path, "wb") as fh:
        fh.write(b"mudrft benchmark".ljust(80) + np.uint32(len(triangles)).tobytes())
        fh.write(rows.tobytes())


def run(n: int = 354) -> dict[str, float]:
    """Write the STL, load it in a child process; the child's numbers and the file size."""
    vertices, faces = semisphere_mesh(0.045, 0.026, resolution=n)
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "foot.stl"
        write_binary_stl(path, 1e3 * vertices[faces])  # in mm, as CAD exports
        child = subprocess.run(
            [sys.executable, "-c", _CHILD, str(path)], capture_output=True, text=True, check=True
        )
        result = json.loads(child.stdout)
        result["file_bytes"] = path.stat().st_size
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=354, help="resolution: 8 n^2 facets")
    parser.add_argument("--json", help="write the numbers as JSON to this file")
    args = parser.parse_args()
    res = run(args.n)
    print(
        f"MeshFoot.from_file, binary STL of {res['facets']:,} facets "
        f"({res['file_bytes'] / 1e6:.0f} MB): {res['seconds']:.2f} s, "
        f"peak memory {res['peak_bytes'] / 2**20:.0f} MiB above the imports"
    )
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
