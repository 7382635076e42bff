"""Tests of the `keel` command's outputs and exit status (every command): the exit table (0 done, 1 done but not
what was asked, 2 usage, 3 bad input, 4 cannot write an output), outputs refused before the work (an input, an
existing file of another kind, an unwritable path), all-or-nothing writes (a failing run leaves every existing file
byte for byte; no temporary file is left behind), `keel --version`, and Ceres's log under --quiet.

Run by CTest (cli.outputs) with KEEL set to the binary; from this folder: KEEL=../../build/release/keel
/usr/bin/python3 -m unittest -v test_outputs.
"""
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

from cli_fixtures import K4_ANGLES, KEEL, REPO, SQUARE, complete_graph

K4 = complete_graph(4, K4_ANGLES)
CANDIDATES = 'EDGE_SE2 0 1 2.01 -0.02 1.575796 100 0 0 100 0 400\nEDGE_SE2 2 6 0 0.01 -0.015 50 0 0 50 0 200\n'
PROSE = 'A JSON-free note a user keeps beside the data.\n'
SURVEY = 'x,y,f\n0,0,1\n10,0,2\n0,10,3\n10,10,4\n'

FILE_COMMANDS = ("check", "solve", "marginals", "pcm", "split", "align", "align-world")
REPRO_COMMANDS = ("list", "diff", "bless", "report", "eta", "prose-check", "same")


class Scratch(unittest.TestCase):
    """Each test in a fresh folder with the fixtures; no temporary output file may be left in it."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="keel-outputs-")
        for name, text in (("square.g2o", SQUARE), ("a.g2o", SQUARE), ("b.g2o", SQUARE), ("k4.g2o", K4),
                           ("candidates.g2o", CANDIDATES), ("notes.txt", PROSE)):
            self.put(name, text)

    def tearDown(self):
        stray = [os.path.join(root, n) for root, dirs, files in os.walk(self.dir) for n in files + dirs
                 if ".keel-" in n or n.endswith(".tmp")]
        shutil.rmtree(self.dir, ignore_errors=True)
        self.assertEqual(stray, [], "temporary files left behind")

    def path(self, name):
        return os.path.join(self.dir, name)

    def put(self, name, text):
        os.makedirs(os.path.dirname(self.path(name)), exist_ok=True)
        with open(self.path(name), "w") as f:
            f.write(text)

    def bytes(self, name):
        with open(self.path(name), "rb") as f:
            return f.read()

    def keel(self, *args, expect=0):
        p = subprocess.run([KEEL, *args], cwd=self.dir, capture_output=True, text=True, timeout=300)
        if p.returncode != expect:
            raise AssertionError(f"keel {' '.join(args)}: exit {p.returncode}, expected {expect}\n"
                                 f"stdout:\n{p.stdout}\nstderr:\n{p.stderr}")
        return p.stdout, p.stderr

    def refused(self, args, kept, text, work_stage=None):
        """keel ARGS exits 4 naming `text`, every file of `kept` byte for byte as it was, and (work_stage) before
        the stage line that starts the work."""
        before = {k: self.bytes(k) for k in kept}
        _, err = self.keel(*args, expect=4)
        self.assertIn(text, err)
        for k in kept:
            self.assertEqual(self.bytes(k), before[k], f"{k} changed")
        if work_stage:
            self.assertNotIn(work_stage, err)
        return err


class Version(unittest.TestCase):
    def test_version_names_the_commit(self):
        p = subprocess.run([KEEL, "--version"], capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertRegex(p.stdout.strip(), r"^keel \d+\.\d+(\.\d+)? \(commit ([0-9a-f]{12}(-dirty)?|unknown)\)$")

    def test_every_help_has_the_exit_table(self):
        for args in ([], *([c] for c in FILE_COMMANDS + REPRO_COMMANDS)):
            p = subprocess.run([KEEL, *args, "--help"], capture_output=True, text=True, timeout=60)
            self.assertEqual(p.returncode, 0, args)
            text = " ".join(p.stdout.split())
            for item in ("Exit status: 0 done;", "2 bad command line", "an option value keel refuses", "3 an input that cannot be read",
                         "4 an output that cannot be written"):
                self.assertIn(item, text, args)
        p = subprocess.run([KEEL, "--help"], capture_output=True, text=True, timeout=60)
        self.assertIn("--version", p.stdout)


class ExitTable(Scratch):
    def test_usage_is_2_for_every_command(self):
        for c in FILE_COMMANDS + REPRO_COMMANDS:
            self.keel(c, "--no-such-option", expect=2)
        self.keel(expect=2)
        self.keel("pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o", "--merged", "m.json",
                  expect=2)

    def test_bad_input_is_3(self):
        self.keel("check", "missing.g2o", expect=3)
        self.keel("solve", "missing.g2o", expect=3)
        self.keel("marginals", "missing.g2o", "--poses", "1", expect=3)
        self.keel("pcm", "--a", "missing.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o", expect=3)
        self.keel("split", "missing.g2o", "--ground-truth", "missing.txt", "--out-dir", "s", expect=3)
        self.assertFalse(os.path.exists(self.path("s")), "the folder of a failed split is removed again")
        self.put("ref.csv", SURVEY)
        self.keel("align", "ref.csv", "missing.csv", expect=3)
        self.keel("align-world", "w", "--terrain", "missing.grid", expect=3)
        self.assertFalse(os.path.exists(self.path("w")))

    def test_not_certified_is_1_and_writes_nothing(self):
        self.put("out.g2o", SQUARE)
        before = self.bytes("out.g2o")
        _, err = self.keel("solve", "k4.g2o", "--certify", "--out", "out.g2o", "--quiet", expect=1)
        self.assertIn("not certified", err)
        self.assertIn("out.g2o not written", err)
        self.assertEqual(self.bytes("out.g2o"), before)
        out, _ = self.keel("solve", "square.g2o", "--certify", "--out", "out.g2o", "--quiet")
        self.assertIn("written      out.g2o", out)
        self.assertNotEqual(self.bytes("out.g2o"), before)

    def test_cannot_write_is_4_with_the_reason_before_the_work(self):
        for args, out in ((["solve", "square.g2o"], "--out"), (["solve", "square.g2o", "--certify"], "--out"),
                          (["marginals", "square.g2o", "--poses", "1"], "--out"),
                          (["pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o"], "--out"),
                          (["pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o"], "--merged")):
            target = "no-such-folder/x.json" if out == "--out" and args[0] != "solve" else "no-such-folder/x.g2o"
            _, err = self.keel(*args, out, target, expect=4)
            self.assertIn(f"{target}: cannot write: No such file or directory", err)
            self.assertNotIn("solving", err)  # refused before the work's first stage
            self.assertNotIn("certified solve", err)
            self.assertNotIn(".tmp", err)
            # A regular file where a folder is expected.
            target = "square.g2o/x" + os.path.splitext(target)[1]
            _, err = self.keel(*args, out, target, expect=4)
            self.assertIn(f"{target}: cannot write: Not a directory", err)
        _, err = self.keel("split", "square.g2o", "--ground-truth", "square.g2o", "--out-dir", "notes.txt/s",
                           expect=4)
        self.assertIn("notes.txt/s: cannot create the folder", err)
        _, err = self.keel("align-world", "notes.txt", expect=4)
        self.assertIn("notes.txt: dir exists and is not a folder", err)


class ReproductionCommands(Scratch):
    EXPERIMENTS = os.path.join(REPO, "experiments")

    def first_id(self):
        out, _ = self.keel("list", "--experiments", self.EXPERIMENTS)
        return out.split()[0]

    def test_a_missing_folder_or_file_is_3(self):
        for c in ("list", "diff", "eta", "report"):
            _, err = self.keel(c, "--experiments", "nope", expect=3)
            self.assertIn("nope: not a folder", err)
        _, err = self.keel("prose-check", expect=3)  # no experiments/ in the scratch folder
        self.assertIn("experiments: not a folder", err)
        ident = self.first_id()
        _, err = self.keel("diff", "--experiments", self.EXPERIMENTS, "--results", "r", ident, expect=3)
        self.assertIn("1 experiment(s) could not be compared", err)
        _, err = self.keel("bless", "--experiments", self.EXPERIMENTS, "--results", "r", ident, expect=3)
        self.assertIn("latest.json: not found", err)
        self.assertFalse(os.path.exists(self.path("r")))
        self.put("one.json", '{"metrics": {"a": 1}}\n')
        _, err = self.keel("same", "one.json", "missing.json", expect=3)
        self.assertIn("missing.json: not found", err)
        self.keel("same", "one.json", "square.g2o", expect=3)

    def test_results_that_differ_are_1(self):
        self.put("one.json", '{"metrics": {"a": 1}}\n')
        self.put("two.json", '{"metrics": {"a": 2}}\n')
        self.keel("same", "one.json", "one.json")
        self.keel("same", "one.json", "two.json", expect=1)

    def test_an_unwritable_paper_folder_is_4_before_the_work(self):
        _, err = self.keel("report", "--experiments", self.EXPERIMENTS, "--results", "r", "--paper", "square.g2o/p",
                           expect=4)
        self.assertIn("square.g2o/p: --paper cannot be created: square.g2o is not a folder", err)


class OutputIsInput(Scratch):
    def test_marginals_out_equal_to_its_graph(self):
        for spelling in ("square.g2o", "./square.g2o", os.path.join(self.dir, "square.g2o")):
            self.refused(["marginals", "square.g2o", "--poses", "1", "--out", spelling], ["square.g2o"],
                         "is the input file", "solving")
        os.symlink("square.g2o", self.path("link.g2o"))
        self.refused(["marginals", "square.g2o", "--poses", "1", "--out", "link.g2o"], ["square.g2o"],
                     "is the input file")
        self.put("pairs.txt", "1 2\n")
        self.refused(["marginals", "square.g2o", "--pairs", "pairs.txt", "--out", "pairs.txt"], ["pairs.txt"],
                     "is the input --pairs")

    def test_solve_out_equal_to_its_graph(self):
        self.refused(["solve", "square.g2o", "--out", "square.g2o"], ["square.g2o"], "is the input file", "solving")

    def test_pcm_merged_over_robot_a(self):
        args = ["pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o"]
        self.refused(args + ["--merged", "a.g2o"], ["a.g2o"], "a.g2o: --merged is the input --a (a.g2o)")
        self.refused(args + ["--out", "candidates.g2o"], ["candidates.g2o"], "is the input --candidates")
        self.refused(args + ["--merged", "m.g2o", "--out", "m.g2o"], [], "given for two outputs")
        self.assertFalse(os.path.exists(self.path("m.g2o")))

    def test_split_into_the_folder_of_its_graph(self):
        self.refused(["split", "a.g2o", "--ground-truth", "square.g2o", "--out-dir", "."], ["a.g2o"],
                     "refusing to replace a.g2o")


class ExistingOutputOfAnotherKind(Scratch):
    def test_json_output_over_a_graph_or_a_note(self):
        self.refused(["marginals", "square.g2o", "--poses", "1", "--out", "b.g2o"], ["b.g2o"],
                     "b.g2o: --out exists and is not a JSON document")
        self.refused(["marginals", "square.g2o", "--poses", "1", "--out", "notes.txt"], ["notes.txt"],
                     "is not a JSON document")
        self.put("m.json", '{"old": 1}\n')
        self.keel("marginals", "square.g2o", "--poses", "1", "--out", "m.json", "--quiet")
        self.assertIn(b'"covariance"', self.bytes("m.json"))

    def test_graph_output_over_a_note(self):
        self.refused(["solve", "square.g2o", "--out", "notes.txt"], ["notes.txt"],
                     "notes.txt: --out exists and is not a pose graph")
        os.mkdir(self.path("folder.g2o"))
        self.refused(["solve", "square.g2o", "--out", "folder.g2o"], [], "is not a regular file")
        self.keel("solve", "square.g2o", "--out", "b.g2o", "--quiet")  # a graph replaces a graph
        self.assertNotEqual(self.bytes("b.g2o"), SQUARE.encode())

    def test_align_world_over_a_users_query_csv(self):
        self.put("query.csv", SURVEY)
        self.refused(["align-world", "."], ["query.csv"], "refusing to replace query.csv")
        self.assertFalse(os.path.exists(self.path("reference.csv")))
        # A folder an earlier align-world wrote is written again; a changed set is refused.
        self.keel("align-world", "w", "--quiet")
        first = self.bytes("w/query.csv")
        self.keel("align-world", "w", "--index", "1", "--quiet")
        self.assertNotEqual(self.bytes("w/query.csv"), first)
        self.put("w/truth.csv", "my truth\n")
        self.refused(["align-world", "w"], ["w/query.csv", "w/truth.csv"], "truth.csv: dir exists and is not")

    def test_split_over_a_users_labels(self):
        self.put("s/labels.txt", "0 inlier -1\n")
        self.refused(["split", "square.g2o", "--ground-truth", "square.g2o", "--out-dir", "s"], ["s/labels.txt"],
                     "refusing to replace labels.txt")

    def test_split_again_into_its_own_folder(self):
        self.put("gt.txt", "".join(" ".join(line.split()[1:5]) + "\n" for line in SQUARE.splitlines()
                                   if line.startswith("VERTEX_SE2")))
        args = ["split", "square.g2o", "--ground-truth", "gt.txt", "--out-dir", "t", "--split", "4", "--last", "8",
                "--inliers", "1", "--aliased-groups", "0", "--quiet"]
        self.keel(*args, "--random-outliers", "1")
        self.keel(*args, "--random-outliers", "2")  # the complete set an earlier split wrote is replaced
        self.assertEqual(self.bytes("t/candidates.g2o").count(b"EDGE_SE2"), 3)
        self.put("t/truth.txt", "my own truth\n")
        self.refused(args, ["t/truth.txt", "t/a.g2o"], "t/truth.txt: --out-dir exists and is not")


class FailingRunsChangeNothing(Scratch):
    def test_pcm_with_short_labels_keeps_the_merged_map(self):
        self.put("short.txt", "0 inlier -1\n")
        self.put("m.g2o", SQUARE)
        self.put("p.json", '{"earlier": true}\n')
        before = (self.bytes("m.g2o"), self.bytes("p.json"))
        _, err = self.keel("pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o", "--labels",
                           "short.txt", "--merged", "m.g2o", "--out", "p.json", expect=3)
        self.assertIn("short.txt: 1 labels for 2 candidates", err)
        self.assertEqual((self.bytes("m.g2o"), self.bytes("p.json")), before)
        # With labels for both, the same command writes both.
        self.put("labels.txt", "0 inlier -1\n1 inlier -1\n")
        self.keel("pcm", "--a", "a.g2o", "--b", "b.g2o", "--candidates", "candidates.g2o", "--labels",
                  "labels.txt", "--merged", "m.g2o", "--out", "p.json", "--quiet")
        self.assertNotEqual((self.bytes("m.g2o"), self.bytes("p.json")), before)

    def test_a_failed_solve_keeps_its_out(self):
        # An information matrix that is not positive definite: the anisotropic solve refuses the file (exit 3).
        self.put("coupled.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 3 1 0 1\n")
        self.put("out.g2o", SQUARE)
        _, err = self.keel("solve", "coupled.g2o", "--out", "out.g2o", expect=3)
        self.assertIn("not positive definite", err)
        self.assertIn("`keel solve --certify` reads this file", err)
        self.assertEqual(self.bytes("out.g2o"), SQUARE.encode())

    def test_solve_from_a_pipe_writes_its_out_once_named(self):
        def run(out):
            return subprocess.run(["bash", "-c", f'"{KEEL}" solve <(cat square.g2o) --out {out} --quiet'],
                                  cwd=self.dir, capture_output=True, text=True, timeout=60)
        p = run("x.sol")  # no extension that names a format: the input's, found in its one reading
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertTrue(self.bytes("x.sol").startswith(b"VERTEX_SE2 0 "))
        p = run("x.g2o")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertTrue(self.bytes("x.g2o").startswith(b"VERTEX_SE2 0 "))

    def test_a_signal_during_the_work_leaves_no_temporary(self):
        # The input is a FIFO nobody writes: keel reserves its outputs (their temporaries appear), then blocks
        # reading; SIGTERM or SIGINT there must remove the temporaries and the folder it created.
        os.mkfifo(self.path("pipe.g2o"))
        for sig, args in ((signal.SIGTERM, ["solve", "pipe.g2o", "--out", "x.g2o"]),
                          (signal.SIGINT, ["split", "pipe.g2o", "--ground-truth", "square.g2o", "--out-dir", "s/t"])):
            p = subprocess.Popen([KEEL, *args, "--quiet"], cwd=self.dir, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL)
            try:
                for _ in range(600):  # up to 60 s for the temporaries to appear
                    if any(".keel-" in n for _, dirs, files in os.walk(self.dir) for n in files + dirs):
                        break
                    time.sleep(0.1)
                else:
                    self.fail(f"keel {' '.join(args)}: no temporary appeared")
                p.send_signal(sig)
                self.assertEqual(p.wait(timeout=60), -sig)
            finally:
                if p.poll() is None:
                    p.kill()
            self.assertFalse(os.path.exists(self.path("x.g2o")))
            self.assertFalse(os.path.exists(self.path("s")), "the folders split created are removed")
        os.remove(self.path("pipe.g2o"))

    def test_outputs_keep_the_usual_permissions(self):
        self.keel("solve", "square.g2o", "--out", "new.g2o", "--quiet")
        mask = os.umask(0)
        os.umask(mask)
        self.assertEqual(os.stat(self.path("new.g2o")).st_mode & 0o777, 0o666 & ~mask)
        # A replaced file keeps its own.
        os.chmod(self.path("new.g2o"), 0o640)
        self.put("m.json", "{}\n")
        os.chmod(self.path("m.json"), 0o600)
        self.keel("solve", "square.g2o", "--out", "new.g2o", "--init", "as-read", "--quiet")
        self.keel("marginals", "square.g2o", "--poses", "1", "--out", "m.json", "--quiet")
        self.assertEqual(os.stat(self.path("new.g2o")).st_mode & 0o777, 0o640)
        self.assertEqual(os.stat(self.path("m.json")).st_mode & 0o777, 0o600)


class SolverLog(Scratch):
    def test_ceres_is_silent_under_quiet_and_a_stage_line_otherwise(self):
        # More threads than Ceres's threading model offers: Ceres warns (through glog) and bounds them.
        _, err = self.keel("solve", "square.g2o", "--threads", "1000000", "--quiet")
        self.assertEqual(err, "")
        _, err = self.keel("solve", "square.g2o", "--threads", "1000000")
        self.assertRegex(err, r"keel solve \[[0-9.]+ s\] Ceres warning:\n    Specified options.num_threads: 1000000")
        self.assertNotRegex(err, r"(?m)^[IWEF]\d{8} ")  # no glog line of its own
        self.assertNotIn("InitGoogleLogging", err)

    def test_ceres_is_silent_in_python(self):
        # The module drops Ceres's log (app::route_solver_log) as `keel solve --quiet` does: the outcome is in the
        # returned summary.
        module = os.path.join(os.path.dirname(KEEL), "python")
        if not os.path.isdir(module):
            self.skipTest(f"no Python module beside {KEEL}")
        code = ("import keel\n"
                "g = keel.read_graph('square.g2o')\n"
                "keel.solve(g, threads=1000000)\n"
                "print('solved')\n")
        p = subprocess.run(["/usr/bin/python3", "-c", code], cwd=self.dir, capture_output=True, text=True,
                           timeout=300, env={**os.environ, "PYTHONPATH": module})
        if "No module named" in p.stderr:
            self.skipTest(p.stderr.strip().splitlines()[-1])
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout, "solved\n")
        self.assertEqual(p.stderr, "")


if __name__ == "__main__":
    unittest.main()
