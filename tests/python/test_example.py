"""The README's example (examples/error_sweep.py) runs, at a tiny size, and writes its plot."""

import os
import subprocess
import sys

from conftest import ROOT


def test_error_sweep_example(tmp_path):
    plot = tmp_path / "sweep.png"
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "error_sweep.py"), "--resolution", "16x12",
         "--vpls", "300", "--errors", "0.01,0.5", "-o", str(plot)],
        capture_output=True, text=True, env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("vpl (exact over ")
    assert [l.split(":")[0] for l in lines[1:3]] == ["lightcuts.error=0.01", "lightcuts.error=0.5"]
    # A looser threshold is not more accurate than a tighter one on the same point lights.
    error = [float(l.split("relative RMS error ")[1].split(",")[0]) for l in lines[1:3]]
    assert error[0] <= error[1]
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
