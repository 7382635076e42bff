"""keel as another project's dependency (README "Using keel from another project"). Run by CTest:

  install.consumer  `cmake --install` of the tree under test into a fresh prefix; examples/consumer configured with
                    find_package(keel) against that prefix, built (its BMIs compiled from the installed module
                    interfaces) and run on a 2D and a 3D graph: the same cost and proven bound, to the last bit, as
                    the installed `keel solve --certify --json`; a bad file exits 3 with the located error; the
                    versions of the command, the CMake package and pyproject.toml are the project's.
  install.pip       the same install, then `pip install --no-build-isolation --no-index .` of this checkout into a
                    fresh virtual environment with system site packages, built against the installed keel
                    (KEEL_USE_INSTALLED_ENGINE); that environment's interpreter, without PYTHONPATH, imports keel from
                    its own site-packages and runs the Python session of docs/USING.md (tests/python/test_using.py).

Environment: KEEL_BUILD_DIR (the build tree to install), KEEL_CXX and KEEL_SCAN_DEPS (its compiler and dependency
scanner), CMAKE_COMMAND, KEEL_PROJECT_VERSION.
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BUILD = os.environ.get("KEEL_BUILD_DIR", "")
CMAKE = os.environ.get("CMAKE_COMMAND", "cmake")
VERSION = os.environ.get("KEEL_PROJECT_VERSION", "")


def run(args, **kw):
    p = subprocess.run(args, capture_output=True, text=True, **kw)
    return p


def must(args, what, **kw):
    p = run(args, **kw)
    if p.returncode != 0:
        raise AssertionError(f"{what} failed (exit {p.returncode}): {' '.join(args)}\n{p.stdout[-4000:]}\n"
                             f"{p.stderr[-4000:]}")
    return p


def install(prefix):
    if not BUILD or not os.path.isfile(os.path.join(BUILD, "CMakeCache.txt")):
        raise unittest.SkipTest("KEEL_BUILD_DIR names no configured build tree")
    must([CMAKE, "--install", BUILD, "--prefix", prefix], "cmake --install")


def ring_g2o_2d(path, n=24):
    """A 2D loop with odometry and two loop closures, slightly inconsistent (so the optimum is not zero)."""
    with open(path, "w") as f:
        for i in range(n):
            a = 2 * math.pi * i / n
            f.write(f"VERTEX_SE2 {i} {5 * math.cos(a):.6f} {5 * math.sin(a):.6f} {a + math.pi / 2:.6f}\n")
        step = 2 * 5 * math.sin(math.pi / n)
        info = "100 0 0 100 0 400"
        for i in range(n):
            j = (i + 1) % n
            f.write(f"EDGE_SE2 {i} {j} {step * (1 + 0.01 * (i % 3)):.6f} {0.002 * (i % 5):.6f} "
                    f"{2 * math.pi / n + 0.003 * (i % 2):.6f} {info}\n")
        f.write(f"EDGE_SE2 0 {n // 2} {0.0:.6f} {10.05:.6f} {math.pi:.6f} {info}\n")
        f.write(f"EDGE_SE2 {n // 4} {3 * n // 4} {0.02:.6f} {9.97:.6f} {math.pi - 0.01:.6f} {info}\n")


def chain_g2o_3d(path, n=12):
    """A 3D chain closed into a loop, with small inconsistencies."""
    info = " ".join("100" if r == c else "0" for r in range(6) for c in range(r, 6))
    with open(path, "w") as f:
        for i in range(n):
            f.write(f"VERTEX_SE3:QUAT {i} {i:.1f} 0 0 0 0 0 1\n")
        for i in range(n - 1):
            f.write(f"EDGE_SE3:QUAT {i} {i + 1} {1 + 0.01 * (i % 3):.4f} {0.01 * (i % 2):.4f} 0 0 0 "
                    f"{0.005 * (i % 3):.4f} {math.sqrt(1 - (0.005 * (i % 3)) ** 2):.8f} {info}\n")
        f.write(f"EDGE_SE3:QUAT 0 {n - 1} {n - 1 + 0.05:.4f} 0.02 0 0 0 0 1 {info}\n")


class Consumer(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="keel-install-consumer-")
        cls.prefix = os.path.join(cls.work, "prefix")
        install(cls.prefix)
        build = os.path.join(cls.work, "consumer")
        must([CMAKE, "-S", os.path.join(REPO, "examples", "consumer"), "-B", build, "-G", "Ninja",
              f"-DCMAKE_PREFIX_PATH={cls.prefix}", "-DCMAKE_BUILD_TYPE=Release",
              f"-DCMAKE_CXX_COMPILER={os.environ['KEEL_CXX']}",
              f"-DCMAKE_CXX_COMPILER_CLANG_SCAN_DEPS={os.environ['KEEL_SCAN_DEPS']}"], "configuring examples/consumer")
        must([CMAKE, "--build", build], "building examples/consumer")
        cls.certify = os.path.join(build, "keel_certify")
        cls.keel = os.path.join(cls.prefix, "bin", "keel")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def consumer_numbers(self, out):
        fields = dict(re.findall(r"^(\w[\w ]*?)\s{2,}(.*)$", out, re.M))
        return fields

    def check_against_keel(self, graph, dim):
        args = [self.certify, graph] + ([dim] if dim == "3d" else [])
        p = run(args)
        self.assertEqual(p.returncode, 0, p.stderr + p.stdout)
        fields = self.consumer_numbers(p.stdout)
        k = run([self.keel, "solve", "--certify", "--json", "-q", graph])
        self.assertEqual(k.returncode, 0, k.stderr)
        cert = json.loads(k.stdout)["certificate"]
        self.assertTrue(cert["certified"] and cert["proven"])
        # The same engine, the same defaults: the same doubles, printed to 17 significant digits.
        self.assertEqual(float(fields["cost"]), cert["final_cost"])
        self.assertEqual(fields["lower bound"], f"{float(fields['lower bound'].split()[0]):.17g} (proven)")
        self.assertEqual(float(fields["lower bound"].split()[0]), cert["lower_bound"])
        self.assertLessEqual(cert["lower_bound"], cert["final_cost"])
        self.assertEqual(fields["termination"], "certified")

    def test_2d_graph_same_numbers_as_the_installed_command(self):
        graph = os.path.join(self.work, "ring.g2o")
        ring_g2o_2d(graph)
        self.check_against_keel(graph, "2d")

    def test_3d_graph_same_numbers_as_the_installed_command(self):
        graph = os.path.join(self.work, "chain.g2o")
        chain_g2o_3d(graph)
        self.check_against_keel(graph, "3d")

    def test_bad_input_is_a_located_error(self):
        graph = os.path.join(self.work, "bad.g2o")
        with open(graph, "w") as f:
            f.write("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 abc 1 0 0 1 0 1\n")
        p = run([self.certify, graph])
        self.assertEqual(p.returncode, 3, p.stdout)
        self.assertIn("bad.g2o:2", p.stderr)
        self.assertIn("'abc' is not a number", p.stderr)
        self.assertEqual(run([self.certify]).returncode, 2)

    def test_one_version_everywhere(self):
        self.assertTrue(VERSION, "KEEL_PROJECT_VERSION is not set")
        p = must([self.keel, "--version"], "keel --version")
        self.assertTrue(p.stdout.startswith(f"keel {VERSION} "), p.stdout)
        with open(os.path.join(self.prefix, "lib", "cmake", "keel", "keelConfigVersion.cmake")) as f:
            self.assertIn(f'set(PACKAGE_VERSION "{VERSION}")', f.read())
        with open(os.path.join(REPO, "pyproject.toml")) as f:
            regex = re.search(r"^regex = '(.*)'$", f.read(), re.M).group(1)
        with open(os.path.join(REPO, "CMakeLists.txt")) as f:
            self.assertEqual(re.search(regex, f.read()).group("value"), VERSION)


class Pip(unittest.TestCase):
    def test_pip_install_into_a_venv_runs_the_using_session(self):
        work = tempfile.mkdtemp(prefix="keel-install-pip-")
        try:
            prefix = os.path.join(work, "prefix")
            install(prefix)
            venv = os.path.join(work, "venv")
            must(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv], "python3 -m venv")
            python = os.path.join(venv, "bin", "python")
            env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
            must([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", REPO,
                  f"--config-settings=build-dir={os.path.join(work, 'build')}",
                  "--config-settings=cmake.define.KEEL_USE_INSTALLED_ENGINE=ON",
                  f"--config-settings=cmake.define.CMAKE_PREFIX_PATH={prefix}",
                  f"--config-settings=cmake.define.CMAKE_CXX_COMPILER={os.environ['KEEL_CXX']}",
                  f"--config-settings=cmake.define.CMAKE_CXX_COMPILER_CLANG_SCAN_DEPS={os.environ['KEEL_SCAN_DEPS']}"],
                 "pip install .", env=env, cwd=work)
            p = must([python, "-c", "import keel; print(keel.__file__); print(keel.__version__)"], "import keel",
                     env=env, cwd=work)
            where, version = p.stdout.split()
            self.assertTrue(os.path.realpath(where).startswith(os.path.realpath(venv)), where)
            self.assertEqual(version, VERSION)
            must([python, "-m", "unittest", "-v", "test_using"], "the docs/USING.md session",
                 env=env, cwd=os.path.join(REPO, "tests", "python"))
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    unittest.main()
