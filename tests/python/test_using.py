"""Runs the Python session of docs/USING.md exactly as written there (the first ```python block), in a scratch
folder with matplotlib's Agg backend, and checks what it prints and draws. Run by CTest (python.using)."""
import os
import re
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def datasets_root():
    for root in (os.environ.get("KEEL_DATASETS"), os.path.join(REPO, "datasets", "cache"),
                 os.path.join(REPO, "..", "shared", "datasets")):
        if root and os.path.exists(os.path.join(root, "manhattan3500", "isam", "manhattanOlson3500.txt")):
            return os.path.abspath(root)
    raise unittest.SkipTest("Manhattan3500 not found")


class UsingSession(unittest.TestCase):
    def test_session_runs_as_documented(self):
        with open(os.path.join(REPO, "docs", "USING.md")) as f:
            blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
        self.assertEqual(len(blocks), 1, "docs/USING.md should hold one Python session")
        env = dict(os.environ, MPLBACKEND="Agg", KEEL_DATASETS=datasets_root())
        # A scratch folder inside the checkout: keel.dataset_file finds datasets/manifest.toml above it.
        with tempfile.TemporaryDirectory(prefix="scratch-using-", dir=HERE) as d:
            p = subprocess.run([sys.executable, "-c", blocks[0]], cwd=d, env=env, capture_output=True, text=True,
                               timeout=300)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertTrue(os.path.getsize(os.path.join(d, "manhattan_pair.png")) > 10000)
        lines = p.stdout.splitlines()
        self.assertTrue(lines[0].startswith("converged "), lines[0])
        self.assertEqual(lines[1], "(1000, 6, 6)")
        # Both relative-pose σ lines print three positive numbers; the correlation changes them.
        correlated = [float(x) for x in lines[2].split("[")[1].rstrip("]").split()]
        independent = [float(x) for x in lines[3].split("[")[1].rstrip("]").split()]
        self.assertEqual(len(correlated), 3)
        self.assertTrue(all(x > 0 for x in correlated + independent))
        self.assertNotEqual(correlated, independent)


if __name__ == "__main__":
    unittest.main()
