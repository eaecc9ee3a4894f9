"""Drawing a report's figures in this process or in worker processes beside it.

Drawing and fitting a figure is matplotlib's work, single-threaded Python (a report's dozen
figures take seconds), while the numbers each one shows come from the design's compiled
programs in the main process. A :class:`Drawer` with workers hands each figure function its
numbers and a :class:`MemoryTarget` in a worker process (started when the drawer is, so their
imports overlap the main process's work), gets the PNG back as bytes and writes it into the
command's :class:`~diffsense.report.files.OutputFolder` here, in this process: the folder's
checks and its manifest stay in one place. Without workers the figure is drawn at once, into
the folder's :class:`~diffsense.report.files.FileTarget`.

A worker is a fresh interpreter (``python -m diffsense.report.draw_worker``):
never a fork of a process whose JAX threads run, and it never imports the caller's main
script (a notebook or a script without a ``__main__`` guard works as well). It imports
matplotlib and the figure modules, never JAX (``DIFFSENSE_X64=0`` leaves it unimported), and
answers requests on its standard input, one length-prefixed pickle each, on its standard
output. A figure function and its
arguments must be picklable (module-level functions; NumPy arrays, numbers, strings).
"""

from __future__ import annotations

import concurrent.futures
import io
import os
import pickle
import queue
import subprocess
import sys
from pathlib import Path, PurePosixPath
from typing import Callable, List, NamedTuple, Optional


class Drawn(NamedTuple):
    """A figure drawn in a worker: its file (relative to the output folder) and PNG bytes."""

    relative: str
    data: bytes

    @property
    def name(self) -> str:
        return PurePosixPath(self.relative).name


class MemoryTarget:
    """What a figure function saves into in a worker: :meth:`save_figure` returns the PNG as
    :class:`Drawn` instead of writing a file."""

    def __init__(self, relative: str):
        self.relative = relative
        self.name = PurePosixPath(relative).name

    def save_figure(self, fig, dpi: Optional[int] = None) -> Drawn:
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi)
        return Drawn(self.relative, buf.getvalue())


class DrawingError(RuntimeError):
    """A figure a worker could not draw (the message names the worker's exception)."""


class WorkerLost(RuntimeError):
    """A worker process that stopped or could not start: its figure is drawn here instead."""


def _send(stream, obj) -> None:
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(len(data).to_bytes(8, "little"))
    stream.write(data)
    stream.flush()


def _receive(stream):
    header = stream.read(8)
    if len(header) < 8:
        raise EOFError("the drawing worker stopped")
    size = int.from_bytes(header, "little")
    data = stream.read(size)
    if len(data) < size:
        raise EOFError("the drawing worker stopped")
    return pickle.loads(data)


def _serve(stdin, stdout) -> None:
    """A worker's loop: draw each request ``(fn, relative, args, kwargs)`` into a
    :class:`MemoryTarget`; answer ``("ok", Drawn)`` or ``("error", "Type: message")``."""
    from diffsense.report import figures, interval_figures, style

    style.pyplot()
    # the figure modules and matplotlib are imported once, now: the answer names them
    _send(stdout, ("ready", (figures.__name__, interval_figures.__name__)))
    while True:
        try:
            fn, relative, args, kwargs = _receive(stdin)
        except EOFError:
            return
        try:
            answer = ("ok", fn(MemoryTarget(relative), *args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - reported to the caller, which lists the figure as skipped
            answer = ("error", f"{type(exc).__name__}: {exc}")
        _send(stdout, answer)


class _Worker:
    """One worker process and its pipes."""

    def __init__(self):
        # the package this process runs, whatever put it on sys.path (an install, a checkout)
        root = str(Path(__file__).resolve().parents[2])
        path = os.pathsep.join([root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
        # DIFFSENSE_X64=0: importing diffsense then leaves JAX unimported (a worker draws with
        # NumPy and matplotlib alone, and starts 0.6-0.8 s sooner)
        self.process = subprocess.Popen([sys.executable, "-m", "diffsense.report.draw_worker"], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                        env=dict(os.environ, PYTHONPATH=path, DIFFSENSE_X64="0"))
        self.ready = False
        self.lost = False

    def draw(self, request) -> Drawn:
        """The request's figure; raises :class:`WorkerLost` when the worker cannot answer."""
        if self.lost:
            raise WorkerLost("the drawing worker stopped")
        try:
            if not self.ready:
                _receive(self.process.stdout)  # its imports are done
                self.ready = True
            _send(self.process.stdin, request)
            status, value = _receive(self.process.stdout)
        except (EOFError, OSError, pickle.UnpicklingError) as exc:
            self.lost = True
            raise WorkerLost(str(exc)) from exc
        if status != "ok":
            raise DrawingError(value)
        return value

    def close(self) -> None:
        try:
            self.process.stdin.close()
            self.process.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            self.process.kill()
        finally:
            self.process.stdout.close()


class Drawing:
    """One figure being drawn: :meth:`result` waits for it and returns the path written."""

    def __init__(self, folder, future: concurrent.futures.Future, request=None):
        self._folder, self._future, self._request = folder, future, request

    def result(self):
        """The path of the PNG in the output folder; raises what drawing it raised. A figure
        whose worker stopped is drawn here."""
        if self._request is None:
            return self._future.result()
        try:
            out = self._future.result()
        except WorkerLost:
            fn, relative, args, kwargs = self._request
            return fn(self._folder.file(relative), *args, **kwargs)
        return self._folder.write_bytes(out.relative, out.data)


class Drawer:
    """Draws figures into ``folder`` (an :class:`~diffsense.report.files.OutputFolder`), in
    ``workers`` processes (0: here, at once). Use as a context manager, or :meth:`close`."""

    def __init__(self, folder, workers: int = 0):
        self.folder = folder
        self._workers: List[_Worker] = []
        self._free: "queue.Queue[_Worker]" = queue.Queue()
        self._threads: Optional[concurrent.futures.ThreadPoolExecutor] = None
        if workers > 0:
            try:
                for _ in range(workers):
                    self._workers.append(_Worker())
            except OSError:  # no process can be started here: draw in this one
                self.close()
                return
            for w in self._workers:
                self._free.put(w)
            self._threads = concurrent.futures.ThreadPoolExecutor(max_workers=workers,
                                                                  thread_name_prefix="diffsense-draw")

    def _on_worker(self, request) -> Drawn:
        worker = self._free.get()
        try:
            return worker.draw(request)
        finally:
            self._free.put(worker)

    def draw(self, fn: Callable, relative: str, *args, **kwargs) -> Drawing:
        """Draw ``fn(target, *args, **kwargs)`` into the file ``relative`` of the folder."""
        if self._threads is None:
            future: concurrent.futures.Future = concurrent.futures.Future()
            try:
                future.set_result(fn(self.folder.file(relative), *args, **kwargs))
            except Exception as exc:  # noqa: BLE001 - raised again by Drawing.result, as a worker's would be
                future.set_exception(exc)
            return Drawing(self.folder, future)
        self.folder.target(relative)  # refuse an unsafe or foreign file now, before drawing it
        request = (fn, relative, args, kwargs)
        pickle.dumps(request)  # an argument that cannot reach a worker fails here, listed as a skipped figure
        return Drawing(self.folder, self._threads.submit(self._on_worker, request), request)

    def close(self) -> None:
        """Wait for the figures being drawn and stop the workers."""
        if self._threads is not None:
            self._threads.shutdown(wait=True)
            self._threads = None
        for w in self._workers:
            w.close()
        self._workers = []

    def __enter__(self) -> "Drawer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


__all__: List[str] = ["Drawer", "Drawing", "Drawn", "DrawingError", "MemoryTarget", "WorkerLost"]

