"""The loader fuzzer (tests/fuzz/fuzz_loader.py) runs, and a few dozen mutated scenes load and
render without a crash. CI runs it for a minute on its own (scripts/test.sh); README has the
longer run."""
import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("gi._core")
FUZZER = ROOT / "tests" / "fuzz" / "fuzz_loader.py"


def test_a_short_fuzz_run_passes(tmp_path):
    proc = subprocess.run([sys.executable, str(FUZZER), "--seed", "7", "--iterations", "40", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    assert "40 iterations" in proc.stdout and "0 failed" in proc.stdout
    assert (tmp_path / "current.usda").exists() and (tmp_path / "current.txt").exists()


def test_mutations_are_seeded():
    sys.path.insert(0, str(FUZZER.parent))
    import random

    import fuzz_loader
    text = (ROOT / "scenes" / "stress" / "nan_lights.usda").read_text()
    assert fuzz_loader.mutate(text, random.Random(3)) == fuzz_loader.mutate(text, random.Random(3))
    assert fuzz_loader.mutate(text, random.Random(3)) != fuzz_loader.mutate(text, random.Random(4))
