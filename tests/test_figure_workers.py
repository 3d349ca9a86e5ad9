"""Figures drawn by several processes (`mechdyn.figure_workers`): the same files as drawn here, every
error and warning of a copy raised here, nothing left running."""

from __future__ import annotations

import os
import warnings

import matplotlib

matplotlib.use("Agg")

import pytest

from mechdyn.figure_workers import FigureWorkers, plot_workers, save_figures

PARENT = os.getpid()


def _line(k: float):
    import matplotlib.pyplot as plt

    _fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1, 2], [0, k, 2 * k])
    ax.set_title(f"slope {k}")
    return ax


class Curves:
    """A result-like source: picklable, its figures named and made by ``plots()``."""

    def __init__(self, n: int, failing: str | None = None, warning: str | None = None) -> None:
        self.n, self.failing, self.warning = n, failing, warning

    def plots(self):
        return {f"curve_{i}.png": (lambda i=i: self._make(i)) for i in range(self.n)}

    def _make(self, i: int):
        name = f"curve_{i}.png"
        if name == self.failing and os.getpid() != PARENT:
            raise ValueError(f"cannot draw {name}")
        if self.warning and os.getpid() != PARENT:
            warnings.warn(self.warning, UserWarning, stacklevel=1)
        return _line(float(i + 1))


def _no_children_left() -> bool:
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return True
    return False


def test_figures_drawn_by_several_processes_are_the_figures_drawn_by_one(tmp_path):
    one = save_figures(Curves(6), tmp_path / "one", workers=1)
    many = save_figures(Curves(6), tmp_path / "many", workers=3)
    assert [p.name for p in one] == [p.name for p in many] == [f"curve_{i}.png" for i in range(6)]
    for a, b in zip(one, many, strict=True):
        assert a.read_bytes() == b.read_bytes()
    assert _no_children_left()


def test_processes_started_before_the_result_draw_it_when_it_comes(tmp_path):
    with FigureWorkers(3) as drawing:
        drawing.start()
        paths = drawing.draw(Curves(5), tmp_path, prefix="study_")
    assert [p.name for p in paths] == [f"study_curve_{i}.png" for i in range(5)]
    assert all(p.stat().st_size > 1000 for p in paths)
    assert _no_children_left()


def test_figures_that_do_not_pickle_are_drawn_by_copies_that_inherit_them(tmp_path):
    makers = {f"f{i}.png": (lambda i=i: _line(i)) for i in range(4)}  # closures: no pickle
    with FigureWorkers(2) as drawing:
        drawing.start()
        paths = drawing.draw(makers, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in paths)
    assert _no_children_left()


@pytest.mark.parametrize("early", [False, True])
def test_an_error_in_another_process_is_raised_here_as_raised_there(tmp_path, early):
    source = Curves(4, failing="curve_1.png")  # fails only where it is not drawn here
    with FigureWorkers(3, draw_here=False) as drawing:
        if early:
            drawing.start()
        with pytest.raises(ValueError, match=r"cannot draw curve_1\.png"):
            drawing.draw(source, tmp_path)
    assert {p.name for p in tmp_path.iterdir()} == {"curve_0.png", "curve_2.png", "curve_3.png"}
    assert _no_children_left()


def test_a_warning_in_another_process_is_warned_here(tmp_path):
    with pytest.warns(UserWarning, match="a glyph is missing"):
        with FigureWorkers(2, draw_here=False) as drawing:
            drawing.draw(Curves(4, warning="a glyph is missing"), tmp_path)
    assert _no_children_left()


def test_processes_that_get_no_result_stop_at_once():
    drawing = FigureWorkers(3).start()  # one copy now: it forks the others once a result comes
    pids = [c["pid"] for c in drawing._children]
    assert len(pids) == 1
    drawing.close()
    for pid in pids:
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)
    assert _no_children_left()


def test_a_copy_that_cannot_start_more_draws_every_figure_itself(tmp_path, monkeypatch):
    real = FigureWorkers._fork

    def only_here(self, n):  # the copy's own forks fail, as under a limit on processes
        if os.getpid() != PARENT:
            raise OSError("Resource temporarily unavailable")
        return real(self, n)

    monkeypatch.setattr(FigureWorkers, "_fork", only_here)
    with FigureWorkers(3, draw_here=False) as drawing:
        drawing.start()
        paths = drawing.draw(Curves(5), tmp_path)
    assert all(p.stat().st_size > 1000 for p in paths)
    assert _no_children_left()


EARLY = """
import os, sys
from pathlib import Path
from mechdyn.figure_workers import FigureWorkers

class Source:
    def plots(self):
        return {f"f{i}.png": (lambda i=i: self.make(i)) for i in range(6)}

    def make(self, i):
        import matplotlib.pyplot as plt

        with open(sys.argv[2], "a") as log:
            log.write(f"{os.getpid()}\\n")
        fig, ax = plt.subplots(figsize=(2, 1.5))
        ax.plot([0, i])
        return ax

real_serve = FigureWorkers._serve


def serve(self, job, report):  # each copy's start, counted
    with open(sys.argv[2] + ".copies", "a") as log:
        log.write(f"{os.getpid()}\\n")
    with open(sys.argv[2] + ".parents", "a") as log:
        log.write(f"{os.getppid()}\\n")
    return real_serve(self, job, report)


FigureWorkers._serve = serve
source = Source()
if sys.argv[3] == "closure":  # a function made in a function: cloudpickle sends it by value
    source.hook = (lambda: (lambda: None))()
if sys.argv[3] == "lock":  # what nothing pickles: its early copy stops, new ones inherit it
    import threading

    source.hook = threading.Lock()
with FigureWorkers(3) as drawing:
    drawing.start()
    paths = drawing.draw(source, sys.argv[1])
assert all(p.stat().st_size > 500 for p in paths), paths
print("matplotlib here:", "matplotlib.pyplot" in sys.modules)
print("drawn here:", str(os.getpid()) in Path(sys.argv[2]).read_text().split())
print("this process:", os.getpid())
"""


@pytest.mark.parametrize("result", ["pickles", "closure", "lock"])
def test_copies_draw_every_figure_and_this_process_never_imports_matplotlib(tmp_path, result):
    import subprocess
    import sys

    script = tmp_path / "early.py"
    script.write_text(EARLY)
    done = subprocess.run(
        [sys.executable, str(script), str(tmp_path / "out"), str(tmp_path / "log"), result],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "matplotlib here: False" in done.stdout
    assert "drawn here: False" in done.stdout
    drawn_by = (tmp_path / "log").read_text().split()
    assert len(drawn_by) == 6  # each figure once
    # three processes in all drew or could draw: one started early, and then, as this process does not
    # draw, as many as there are processes to have (the early one's two, or two new ones that inherit
    # a result that does not pickle, after the early one stopped)
    copies = (tmp_path / "log.copies").read_text().split()
    # (with a result that nothing pickles, the early copy is stopped: whether it had started by then is
    # the machine's timing, so it is counted or not)
    assert len(copies) in ((3, 4) if result == "lock" else (3,)) and set(drawn_by) <= set(copies)
    # a result that pickles, by pickle or by cloudpickle, reaches the early copy, which forks the
    # others (copies whose parent is the early copy); one that nothing pickles is drawn by this
    # process's own new children only
    here = done.stdout.split("this process: ")[1].split()[0]
    parents = set((tmp_path / "log.parents").read_text().split())
    assert (parents == {here}) == (result == "lock")


def test_the_number_of_processes_follows_the_environment(monkeypatch):
    monkeypatch.setenv("MECHDYN_PLOT_WORKERS", "3")
    assert plot_workers() == 3
    monkeypatch.delenv("MECHDYN_PLOT_WORKERS")
    assert plot_workers() >= 1


class Recorder:
    """A source whose figure notes which of ``watched`` the process drawing it had imported."""

    def __init__(self, log: str, watched: tuple[str, ...]) -> None:
        self.log, self.watched = log, watched

    def plots(self):
        return {"seen.png": self._make}

    def _make(self):
        import sys

        with open(self.log, "w") as out:
            out.write(" ".join(m for m in self.watched if m in sys.modules))
        return _line(1.0)


def test_processes_started_early_import_the_modules_they_are_told_to_expect(tmp_path):
    import sys

    watched = ("wave", "tabnanny")  # modules nothing here imports
    assert not any(m in sys.modules for m in watched)
    log = tmp_path / "seen.txt"
    with FigureWorkers(2, draw_here=False) as drawing:
        drawing.start()
        drawing.expect("wave", "mechdyn.no_such_module")  # one that does not import is passed over
        drawing.expect("tabnanny")  # told twice: both
        drawing.draw(Recorder(str(log), watched), tmp_path)
    assert log.read_text().split() == ["wave", "tabnanny"]
    assert not any(m in sys.modules for m in watched)
    assert _no_children_left()


def test_expecting_modules_without_processes_started_early_is_nothing(tmp_path):
    with FigureWorkers(2) as drawing:
        drawing.expect("wave")
        paths = drawing.draw(Curves(3), tmp_path)
    assert all(p.stat().st_size > 1000 for p in paths)
    assert _no_children_left()


@pytest.mark.parametrize(  # the late start in CI's heavy step; the copies' own tests cover it by default
    "free",
    [True, pytest.param(False, marks=pytest.mark.slow)],
    ids=["a core free: forked early", "no core free: late"],
)
def test_the_command_draws_the_same_plots_whether_a_core_is_free_or_not(tmp_path, monkeypatch, free):
    import mechdyn.figure_workers
    from conftest import EXAMPLES
    from mechdyn.cli.main import main

    monkeypatch.setattr(mechdyn.figure_workers, "core_free", lambda: free)
    started = []
    real = FigureWorkers.start
    monkeypatch.setattr(FigureWorkers, "start", lambda self, *m: started.append(m) or real(self, *m))
    expected = []  # forked before the model is read, the copy is told what its result will hold
    told = FigureWorkers.expect
    monkeypatch.setattr(FigureWorkers, "expect", lambda self, *m: expected.append(m) or told(self, *m))
    model = EXAMPLES / "press_on_mounts.toml"
    argv = ["support", str(model), "--db", str(tmp_path / "r.db"), "--plots"]
    assert main([*argv, str(tmp_path / "plots")]) == 0
    with monkeypatch.context() as m:
        m.setenv("MECHDYN_PLOT_WORKERS", "1")  # every figure drawn in one process: the reference
        assert main([*argv, str(tmp_path / "one")]) == 0
    drawn = sorted(p.name for p in (tmp_path / "plots").iterdir())
    assert drawn and drawn == sorted(p.name for p in (tmp_path / "one").iterdir())
    for name in drawn:
        assert (tmp_path / "plots" / name).read_bytes() == (tmp_path / "one" / name).read_bytes(), name
    # the analysis' module, its plots and what the analysis imports where it runs (its result's class)
    analysis = ("mechdyn.support.analyses", "mechdyn.support.plots")
    assert started[0] == (*analysis, "mechdyn.errors", "mechdyn.support.result", "mechdyn.support.floor")
    assert bool(expected) == free
    if free:
        assert "mechdyn.support.model" in expected[0] and "mechdyn.support.schema" not in expected[0]
    assert _no_children_left()


def test_a_core_is_free_only_where_fewer_processes_run_than_there_are_cores(monkeypatch):
    from mechdyn.figure_workers import core_free

    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0})  # this process runs: none is free
    assert core_free() is False
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(4096)))
    assert core_free() is True


def test_this_process_is_counted_once_however_many_of_its_threads_run(monkeypatch):
    import io

    import mechdyn.figure_workers as fw

    def loadavg(running):  # the kernel's count: every runnable thread of every process
        return lambda *a, **k: io.StringIO(f"0.50 0.40 0.30 {running}/80 4242\n")

    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    monkeypatch.setattr(fw, "_running_here", lambda: 2)  # this thread and NumPy's BLAS worker, say
    monkeypatch.setattr(fw, "open", loadavg(2), raising=False)
    assert fw.core_free() is True  # only this process runs: the other core is idle
    monkeypatch.setattr(fw, "open", loadavg(3), raising=False)
    assert fw.core_free() is False  # another process runs too
    monkeypatch.undo()
    assert fw._running_here() >= 1  # read from /proc: this thread at least, as it reads


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="threads counted in /proc (Linux)")
def test_with_plots_the_linear_algebra_keeps_to_one_thread_unless_the_user_says_otherwise():
    import subprocess
    import sys

    code = (
        "import os\n"
        "from mechdyn.figure_workers import one_blas_thread\n"
        "assert one_blas_thread()\n"
        "import numpy\n"
        "assert not one_blas_thread()  # NumPy imported: too late, nothing changed\n"
        "print(len(os.listdir('/proc/self/task')), os.environ['OPENBLAS_NUM_THREADS'])\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["1", "1"]  # no BLAS worker thread beside this one
    env["OPENBLAS_NUM_THREADS"] = "2"  # the user's own choice is kept
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert done.stdout.split()[1] == "2"


def test_a_result_with_a_tabulated_process_force_goes_to_a_drawing_process_by_the_plain_pickle(tmp_path):
    # a closure over the file's table needed cloudpickle, and unpickling it imported the file reader
    # (pydantic and all) in the drawing process while the figures waited
    import pickle
    import subprocess
    import sys

    import numpy as np

    from conftest import EXAMPLES
    from mechdyn.io.modelfile import load_model
    from mechdyn.registry import analyses

    loaded = load_model(EXAMPLES / "press_tonnage.toml")
    result = analyses()["mechanism"].run(loaded)
    (force,) = result.mechanism.process_forces
    (tmp_path / "result.pickle").write_bytes(pickle.dumps(result))  # would raise for a closure
    code = (
        "import pickle, sys\n"
        f"result = pickle.loads(open({str(tmp_path / 'result.pickle')!r}, 'rb').read())\n"
        "print(sorted(m for m in sys.modules if m.endswith('.schema') or m == 'pydantic'))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
    again = pickle.loads(pickle.dumps(force.force))
    theta = np.linspace(0.0, 2 * np.pi, 50)
    position = np.linspace(-0.2, 0.0, 50)
    np.testing.assert_array_equal(again(theta, position), force.force(theta, position))
