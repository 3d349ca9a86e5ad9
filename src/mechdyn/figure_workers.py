"""A result's figures drawn by several processes.

Drawing a figure is matplotlib's own work, one core per figure, and a run's figures are independent of
each other: where the platform forks a process cheaply and safely (Linux), the figures are shared among
copies of this process. A copy started before the analysis (:meth:`FigureWorkers.start`) imports
matplotlib while it runs, then receives the result, pickled (by cloudpickle where it holds local
functions), and forks the further copies that draw beside it, which inherit matplotlib imported and the
result (importing matplotlib is as much work as drawing three figures: it is done once, and never by
this process when it has not done it already); copies started when the figures are asked for inherit
them. A copy started even before the model is read (where a core is idle, :func:`core_free`) is told
which modules the result will need once the model is read (:meth:`FigureWorkers.expect`), and imports
them while the analysis runs (the command keeps its own linear algebra to one thread,
:func:`one_blas_thread`, so that no BLAS worker spins on the core a copy draws on). Each copy freezes
what it holds out of the garbage collector's reach before it draws, takes the next figure from a queue
when it is free, so that one large figure does not hold up the rest, and ends without running this
process's exit handlers. An error in any copy is raised in this process, as raised there, once every
copy has ended; the figures drawn by then are on disk.
"""

from __future__ import annotations

import gc
import os
import pickle
import signal
import sys
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, cast

from mechdyn.plotting import legend

__all__ = ["FigureWorkers", "core_free", "one_blas_thread", "plot_workers", "save_figures"]

Makers = Mapping[str, Callable[[], Any]]


def plot_workers() -> int:
    """How many processes draw a set of figures: the cores this process may use, where the platform
    forks cheaply and safely (Linux); one elsewhere. ``MECHDYN_PLOT_WORKERS`` sets it."""
    asked = os.environ.get("MECHDYN_PLOT_WORKERS", "").strip()
    if asked.isdigit() and int(asked) > 0:
        return int(asked)
    if not sys.platform.startswith("linux") or not hasattr(os, "fork"):
        return 1  # macOS forks unsafely once system frameworks are loaded; Windows does not fork
    return len(os.sched_getaffinity(0))


def _get_ready(modules: tuple[str, ...]) -> None:
    """What a copy does before its result comes: import matplotlib and the modules that will draw,
    and draw one small figure in memory (the fonts are read and laid out on the first text drawn)."""
    import io

    import matplotlib.pyplot as plt

    from mechdyn.units import registry

    _import(list(modules))
    registry()  # the figures' display units (made already where this process was forked late: kept)
    # the first of each kind of text is slow to lay out: fonts read, glyphs cached, and mathtext's
    # parser (a logarithmic axis' labels) built; a small figure with one of each, drawn while waiting
    fig, axes = plt.subplots(2, 1, figsize=(2, 3), sharex=True, layout="constrained")
    axes[0].plot([1.0, 1000.0], [0.0, 1.0], label="warm-up")
    axes[0].set_xscale("log")
    axes[0].set_title("warm-up")
    axes[0].annotate("TDC", (10.0, 0.5), bbox={"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1})
    axes[1].set_xlabel("x (mm), ω (rad/s²), µm, °")
    legend(axes[0])
    fig.savefig(io.BytesIO(), format="png", dpi=130)
    plt.close(fig)


def _drawn_here() -> bool:
    """Whether this process has matplotlib imported already, so that drawing here costs no import."""
    return "matplotlib.pyplot" in sys.modules


def _drain(queue: int, makers: Makers, paths: list[Path], dpi: int, leave: int = 0) -> None:
    """Draw the figures whose indices this process takes from the queue (four bytes each), leaving
    the last ``leave`` of them to the other processes (which have matplotlib imported already)."""
    import fcntl
    import termios

    from mechdyn.plotting import save_figure

    names = list(makers)
    waiting = bytearray(4)
    while True:
        if leave:
            fcntl.ioctl(queue, termios.FIONREAD, waiting)
            if int.from_bytes(waiting, sys.byteorder) // 4 <= leave:
                return
        record = os.read(queue, 4)
        if len(record) < 4:
            return
        i = int.from_bytes(record, "little")
        save_figure(makers[names[i]](), paths[i], dpi=dpi)


def _pickled(job: Any) -> bytes:
    """A job as bytes for a copy: by the standard pickle, or, where it holds functions made inside other
    functions (a mechanism's tabulated process force, an eccentric pitch curve), by cloudpickle, which
    carries them by value (the copy unpickles either with :func:`pickle.loads`)."""
    try:
        return pickle.dumps(job)
    except Exception:
        import cloudpickle

        return cast(bytes, cloudpickle.dumps(job))


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exactly(fd: int, n: int) -> bytes:
    """``n`` bytes from a pipe, or fewer where it ends first."""
    chunks, left = [], n
    while left and (chunk := os.read(fd, min(left, 1 << 16))):
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


# What goes down a copy's job pipe: frames of one kind byte and eight bytes of length, then the bytes.
_MODULES, _RESULT = b"m", b"r"


def _frame(kind: bytes, data: bytes) -> bytes:
    return kind + len(data).to_bytes(8, "little") + data


def _next_frame(fd: int) -> tuple[bytes, bytes] | None:
    """The next frame of a job pipe, or None where the pipe ends (nothing more to come)."""
    head = _read_exactly(fd, 9)
    if len(head) < 9:
        return None
    data = _read_exactly(fd, int.from_bytes(head[1:], "little"))
    return head[:1], data


def _import(modules: list[str]) -> None:
    import importlib

    for name in modules:
        try:
            importlib.import_module(name)
        except ImportError:  # a module that may not exist (an analysis without plots of its own)
            pass


def one_blas_thread() -> bool:
    """Keep the linear algebra of this process (and of the processes it forks) to one thread, where
    NumPy is not imported yet and the environment does not say otherwise: the other cores draw the
    figures, and a BLAS worker thread spins for a while after each call, taking turns with them (the
    matrices of a run are far too small to gain from more threads). Returns whether it was set.

    Set through ``OPENBLAS_NUM_THREADS`` and ``MKL_NUM_THREADS``, which the libraries read once, when
    NumPy is imported (not ``OMP_NUM_THREADS``, which would reach the compiled kernels' own threads);
    a variable already set is left as it is.
    """
    if "numpy" in sys.modules:
        return False
    for name in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")
    return True


def _running_here() -> int:
    """How many of this process's threads are runnable now (their state ``R`` in ``/proc``): this one,
    and any other, such as a linear-algebra library's worker that spins a while after its work."""
    running = 0
    for tid in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{tid}/stat") as f:
                running += f.read().rpartition(")")[2].split()[0] == "R"
        except (OSError, IndexError):  # a thread that ended meanwhile
            continue
    return max(running, 1)


def core_free() -> bool:
    """Whether a core of those this process may use is idle now: fewer processes runnable at this
    instant than cores, counting this process once (the kernel's count in ``/proc/loadavg`` counts
    every runnable thread, and NumPy's BLAS keeps a worker spinning beside the thread that imported
    it), so that a process started now works beside this one rather than taking turns with it. False
    where it cannot tell."""
    try:
        with open("/proc/loadavg") as f:
            running = int(f.read().split()[3].split("/")[0])
        others = running - _running_here()
        return others + 1 < len(os.sched_getaffinity(0))
    except (OSError, ValueError, IndexError, AttributeError):
        return False


def _report(fd: int, error: BaseException | None, caught: list[warnings.WarningMessage]) -> None:
    """Write a copy's outcome for the parent: its exception (in words, and pickled where it pickles)
    and the warnings it caught (a copy writes nothing to the terminal itself)."""
    said = [(str(w.message), w.category) for w in caught]
    words = None if error is None else f"{type(error).__name__}: {error}"
    try:
        payload = pickle.dumps({"words": words, "error": error, "warnings": said})
    except Exception:
        payload = pickle.dumps({"words": words, "error": None, "warnings": said})
    with os.fdopen(fd, "wb") as out:
        out.write(payload)


def _reported(payload: bytes) -> BaseException | None:
    """Warn again here of what a copy caught; the exception it reported (as raised there where it
    unpickles, else in its words), or None."""
    try:
        report = pickle.loads(payload)
    except Exception as exc:  # an exception that pickles but does not unpickle
        return RuntimeError(f"a process drawing figures failed ({exc})")
    for message, category in report["warnings"]:
        warnings.warn(message, category, stacklevel=2)
    if report["words"] is None:
        return None
    error = report["error"]
    return error if isinstance(error, BaseException) else RuntimeError(report["words"])


class FigureWorkers:
    """Processes that draw figures beside this one; use as a context manager.

    Parameters
    ----------
    workers : int, optional
        Processes in all, this one included; :func:`plot_workers` by default. One draws every figure
        here.
    draw_here : bool
        Whether this process draws too (as it does by default) or only waits for the others.
    """

    def __init__(self, workers: int | None = None, *, draw_here: bool = True) -> None:
        self.workers = max(1, plot_workers() if workers is None else int(workers))
        self.draw_here = draw_here
        self._queue: list[int | None] = [None, None]  # the figures' queue: read end, write end
        self._children: list[dict[str, Any]] = []  # pid, job (write end), report (read end)
        self._inherit: tuple[Makers, list[Path], int] | None = None
        self._job: tuple[Makers, list[Path], int] | None = None  # handed out by begin(), for end()
        self._ready: tuple[str, ...] = ()  # modules a copy started early imports
        self._helpers = 0  # further copies the one started early forks once its result has come

    def __enter__(self) -> FigureWorkers:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def start(self, *modules: str) -> FigureWorkers:
        """Start the other processes now, before the figures exist: they import matplotlib and
        ``modules`` (those of the analysis to come, so that its result unpickles at once), draw a
        first figure to have the fonts ready, and wait for a result to draw.

        Parameters
        ----------
        *modules : str
            Module names to import in each process beforehand.
        """
        if self.workers > 1 and not self._children:
            self._ready = modules
            # one copy now; once its result has come it forks the others, which inherit matplotlib
            # and the result, so that neither is imported nor unpickled twice. This process then
            # draws nothing unless it has matplotlib imported already: the copies draw every figure.
            self._helpers = self.workers - 1
            self._fork(1)
        return self

    def expect(self, *modules: str) -> None:
        """Tell the processes started early which modules the result to come will need (those of the
        model it is made from), so that they import them while it is made, not once it has come.

        Parameters
        ----------
        *modules : str
            Module names; one that does not import is passed over.
        """
        data = _frame(_MODULES, " ".join(modules).encode())
        for child in self._children:
            if child["job"] is not None:
                try:
                    _write_all(child["job"], data)
                except BrokenPipeError:  # that copy has ended: its report says why
                    pass

    def _fork(self, n: int) -> None:
        self._open_queue()
        sys.stdout.flush()
        sys.stderr.flush()
        for _ in range(n):
            job_read, job_write = os.pipe()
            report_read, report_write = os.pipe()
            with warnings.catch_warnings():  # Python 3.12 warns of any thread; none draws in a copy
                warnings.simplefilter("ignore", DeprecationWarning)
                pid = os.fork()
            if pid == 0:  # the copy: never returns into the caller's code
                status = 1
                try:
                    for other in self._children:  # another copy's job pipe must close when we do
                        os.close(other["job"])
                        os.close(other["report"])
                    self._children = []  # this copy's own, if it forks any
                    os.close(job_write)
                    os.close(report_read)
                    status = self._serve(job_read, report_write)
                finally:
                    os._exit(status)
            os.close(job_read)
            os.close(report_write)
            self._children.append({"pid": pid, "job": job_write, "report": report_read})

    def _serve(self, job: int, report: int) -> int:
        """A copy's life: the figures it inherited, or a result to come down its job pipe."""
        error: BaseException | None = None
        caught: list[warnings.WarningMessage] = []
        try:
            self._close_queue(1)
            warnings.simplefilter("always")
            warnings.showwarning = lambda message, category, *a, **k: caught.append(
                warnings.WarningMessage(message, category, "", 0)
            )
            if self._inherit is None:
                _get_ready(self._ready)
                while (frame := _next_frame(job)) is not None and frame[0] == _MODULES:
                    _import(frame[1].decode().split())  # what the result will need, while it is made
                if frame is None:  # nothing to draw after all
                    return 0
                source, paths, dpi = pickle.loads(frame[1])
                makers = source.plots() if hasattr(source, "plots") else source
                more = min(self._helpers, len(paths) - 1)
                if more > 0:  # they report to this copy, which reports for all of them
                    self._children, self._inherit = [], (makers, paths, dpi)
                    try:
                        self._fork(more)
                    except OSError:  # no further process to be had: this one draws them all
                        pass
                    for child in self._children:  # they have their figures: nothing to wait for
                        os.close(child["job"])
                        child["job"] = None
            else:
                makers, paths, dpi = self._inherit
            # what the copy holds now (matplotlib, the result) is kept out of the collector's reach:
            # its full collections, which came while a figure was drawn and walked all of it, cost as
            # much as the figure (the copy ends with its figures: nothing frozen is missed)
            gc.freeze()
            _drain(cast(int, self._queue[0]), makers, paths, dpi)
        except BaseException as exc:  # reported to the parent, which raises it
            error = exc
        found = self._collect()  # the copies this one forked, if any
        _report(report, error or found, caught)
        return 0 if error is None else 1

    def draw(self, source: Any, folder: str | Path, *, prefix: str = "", dpi: int = 130) -> list[Path]:
        """Draw and save every figure of ``source``: :meth:`begin`, then :meth:`end`.

        Parameters
        ----------
        source : Result or mapping of str to callable
            A result (its ``plots()``: file name → function returning the figure or its axes), or
            that mapping itself.
        folder : str or Path
            Where to write them; made if missing.
        prefix : str
            Put before every file name (a study's name where several share the folder).
        dpi : int
            Resolution of a PNG, dots per inch.

        Returns
        -------
        list of Path
            The files, in the order of the figures.
        """
        paths = self.begin(source, folder, prefix=prefix, dpi=dpi)
        self.end()
        return paths

    def begin(self, source: Any, folder: str | Path, *, prefix: str = "", dpi: int = 130) -> list[Path]:
        """Hand the figures of ``source`` to the other processes and return at once, so that this one
        can go on (store the run, print its tables) while they draw; :meth:`end` draws what is left
        here and waits.

        Parameters
        ----------
        source : Result or mapping of str to callable
            As for :meth:`draw`.
        folder : str or Path
            Where to write them; made if missing.
        prefix : str
            Put before every file name.
        dpi : int
            Resolution of a PNG, dots per inch.

        Returns
        -------
        list of Path
            The files that :meth:`end` will have written, in the order of the figures.
        """
        makers: Makers = source.plots() if hasattr(source, "plots") else source
        names = list(makers)
        paths = [Path(folder) / (prefix + n) for n in names]
        self._job = (makers, paths, dpi)
        if not names or ((self.workers <= 1 or len(names) <= 1) and not self._children):
            self.close()
            return paths  # drawn here by end()
        payload = b""
        if self._children:  # started early: they need the result itself
            try:
                payload = _pickled((source, paths, dpi))
            except Exception:  # what even cloudpickle cannot take: those copies stop, new ones inherit it
                self.close()
        try:
            self._hand_out(names, makers, paths, dpi, payload)
        except OSError:  # no process to be had (a limit on processes or pipes): end() draws them here
            self.close()
        return paths

    def _hand_out(
        self, names: list[str], makers: Makers, paths: list[Path], dpi: int, payload: bytes
    ) -> None:
        """Fill the queue and give the copies their work: the result to those started early, the
        figures themselves to those forked now."""
        self._open_queue()
        _write_all(cast(int, self._queue[1]), b"".join(i.to_bytes(4, "little") for i in range(len(names))))
        if not self._children:
            self._inherit = (makers, paths, dpi)
            # this process takes its share only with matplotlib imported already (end()); else as
            # many copies draw as there are processes to have (a result that does not pickle, such
            # as a mechanism with a tabulated process force, comes here after its early copy stopped)
            here = self.draw_here and _drawn_here()
            self._fork(min(self.workers, len(names)) - (1 if here else 0))
        else:
            for child in self._children:
                try:
                    _write_all(child["job"], _frame(_RESULT, payload))
                except BrokenPipeError:  # that copy has ended: its report says why
                    pass
        self._close_queue(1)
        for child in self._children:
            os.close(child["job"])
            child["job"] = None

    def end(self) -> None:
        """Draw here the figures no other process has taken, wait for the others, and raise the first
        error any of them met."""
        from mechdyn.plotting import save_figure

        if self._job is None:
            return
        makers, paths, dpi = self._job
        self._job = None
        error: BaseException | None = None
        try:
            if not self._children:  # no other process: every figure is drawn here
                for name, path in zip(makers, paths, strict=True):
                    save_figure(makers[name](), path, dpi=dpi)
            elif self.draw_here and _drawn_here():
                # more figures than other processes, and matplotlib imported here already: this one
                # takes the surplus (importing it only for that would cost more than it saves)
                _drain(cast(int, self._queue[0]), makers, paths, dpi, leave=len(self._children))
        except BaseException as exc:
            error = exc
        found = self._collect()
        if error is None:
            error = found
        if error is not None:
            raise error

    def _collect(self) -> BaseException | None:
        """Wait for every copy; the first error any reported. A copy still waiting for a result has
        nothing to lose and is stopped at once."""
        error: BaseException | None = None
        for child in self._children:
            if child["job"] is not None:
                os.close(child["job"])
                os.kill(child["pid"], signal.SIGKILL)
                os.close(child["report"])
                os.waitpid(child["pid"], 0)
                continue
            with os.fdopen(child["report"], "rb") as pipe:
                payload = pipe.read()
            _, status = os.waitpid(child["pid"], 0)
            found = _reported(payload) if payload else None
            if found is None and status != 0:
                found = RuntimeError(f"a process drawing figures ended with status {status}")
            error = error or found
        self._children = []
        self._close_queue(0)
        self._close_queue(1)
        self._inherit = None
        return error

    def _open_queue(self) -> None:
        if self._queue[0] is None:
            self._queue = list(os.pipe())

    def _close_queue(self, end: int) -> None:
        """Close one end of the queue once (a number closed twice may by then be another file's)."""
        fd, self._queue[end] = self._queue[end], None
        if fd is not None:
            os.close(fd)

    def close(self) -> None:
        """End the other processes (those still waiting for a result end at once)."""
        self._collect()


def save_figures(
    source: Any, folder: str | Path, *, prefix: str = "", dpi: int = 130, workers: int | None = None
) -> list[Path]:
    """Draw and save every figure of a result, shared among processes where the platform allows
    (:class:`FigureWorkers`).

    Parameters
    ----------
    source : Result or mapping of str to callable
        A result (its ``plots()``: file name → function returning the figure or its axes), or that
        mapping itself.
    folder : str or Path
        Where to write them; made if missing.
    prefix : str
        Put before every file name (a study's name where several share the folder).
    dpi : int
        Resolution of a PNG, dots per inch.
    workers : int, optional
        Processes in all; :func:`plot_workers` by default.

    Returns
    -------
    list of Path
        The files, in the order of the figures.
    """
    with FigureWorkers(workers) as drawing:
        return drawing.draw(source, folder, prefix=prefix, dpi=dpi)
