"""Compiled programs keyed by structure: traced once, kept on disk, compiled in the background.

A program here is a pure function of arrays whose shapes and whose code are fixed by some
*structure* (a design model's scenes, variables and requirements, say), while every number a
user may edit is one of its array inputs. Such a program is the same for every value of those
numbers, so it is

* **exported once** (:mod:`jax.export`): traced and lowered to StableHLO the first time its
  structure is seen, and the serialised module kept in ``<cache>/programs`` under a key made of
  the structure, the program's name and static settings, the shapes of its inputs, the source
  of this package and the JAX version. Later processes load the module instead of tracing
  the Python code again (tracing is what a persistent XLA cache never saves);
* **compiled in a background thread** (XLA compiles without holding Python's lock), so two
  programs compile on two cores while the main thread traces a third or runs a compiled one;
* **kept compiled**: the executable XLA made goes beside the module (``NAME-HASH.xlaexec``,
  keyed by the module's content — the bytes of its StableHLO — the XLA options, jaxlib, the
  device and ``XLA_FLAGS``) and a later process loads it directly, without lowering the module
  again or hashing it for JAX's persistent cache (about a third of a second less per program).
  Modules are exported without source locations, so a change of the package that leaves a
  program's computation alone (which still traces it again) finds its executable. Only an
  executable XLA compiled in this process is stored: one JAX read back from its own persistent
  cache serialises without the kernels XLA:CPU built for it, and loading that copy would fail
  when it runs. So that JAX's cache does not hold such a program without its stored executable
  (which would leave it loading through JAX's cache for good), a program that may be stored is
  compiled under a name of its own (``diffsense_NAME``), apart from entries made by versions of
  this package before the stored executables were keyed by content.

``<cache>`` is the folder of JAX's persistent compilation cache (``jax_compilation_cache_dir``,
which the ``diffsense`` command sets from ``DIFFSENSE_CACHE_DIR``); without one, programs are
exported and compiled once per process. A file that cannot be read is traced again and
rewritten; files are written atomically (a temporary file renamed into place).

Pytree types that appear in a program's inputs or outputs must be registered for serialisation
(:func:`register_serializable`).
"""

from __future__ import annotations

import atexit
import concurrent.futures
import contextlib
import hashlib
import json
import os
import re
import tempfile
import threading
import time
from pathlib import Path
from typing import Callable, Dict, Optional

import jax
import numpy as np

from diffsense.optimize.compile import compiler_options, preset_options
from diffsense.optimize.result import Conflict, KKTResidual, Result, Scales

_PACKAGE = Path(__file__).resolve().parents[1]
_CODE_VERSION: Optional[str] = None
_REGISTERED: set = set()
_LOCK = threading.Lock()
#: compilations of each program name in this process (what the job benchmark and the tests count)
COMPILATIONS: Dict[str, int] = {}
#: traces (exports) of each program name in this process
TRACES: Dict[str, int] = {}
#: every program built in this process, in order (for :func:`report_programs`)
BUILT: list = []
#: environment variable that makes a process print :func:`report_programs` to standard error at exit
LOG_VARIABLE = "DIFFSENSE_PROGRAM_LOG"


def code_version() -> str:
    """A digest of this package's Python source and data (every ``*.py`` and ``*.npz`` file under
    ``diffsense``, e.g. the stored Chebyshev coefficients): a program traced from other code or
    other constants is never reused."""
    global _CODE_VERSION
    if _CODE_VERSION is None:
        h = hashlib.sha256()
        for path in sorted([*_PACKAGE.rglob("*.py"), *_PACKAGE.rglob("*.npz")]):
            h.update(str(path.relative_to(_PACKAGE)).encode())
            h.update(path.read_bytes())
        _CODE_VERSION = h.hexdigest()
    return _CODE_VERSION


def register_serializable(cls, name: Optional[str] = None) -> None:
    """Make the pytree node type ``cls`` serialisable in exported programs: a NamedTuple, or a
    class registered with :func:`jax.tree_util.register_pytree_node_class` whose auxiliary data
    is a tuple of strings (e.g. output names). Idempotent."""
    if cls in _REGISTERED:
        return
    name = name or f"{cls.__module__}.{cls.__qualname__}"
    if issubclass(cls, tuple) and hasattr(cls, "_fields"):
        jax.export.register_namedtuple_serialization(cls, serialized_name=name)
    else:
        jax.export.register_pytree_node_serialization(
            cls, serialized_name=name,
            serialize_auxdata=lambda aux: json.dumps(list(aux)).encode(),
            deserialize_auxdata=lambda data: tuple(json.loads(bytes(data).decode())))
    _REGISTERED.add(cls)


def cache_folder() -> Optional[Path]:
    """``<jax_compilation_cache_dir>/programs``, or None when JAX has no persistent cache."""
    base = jax.config.jax_compilation_cache_dir
    return Path(base) / "programs" if base else None


#: size limit of JAX's persistent compilation cache (bytes), see :func:`lock_compilation_cache`
CACHE_MAX_BYTES = 4 * 2**30
#: marks a cache folder whose entries all have JAX's access-time files (:func:`lock_compilation_cache`)
_LOCKED_MARK = ".diffsense-lru"


def lock_compilation_cache(max_bytes: int = CACHE_MAX_BYTES) -> None:
    """Give JAX's persistent compilation cache (``jax_compilation_cache_dir``, set before) a size
    limit: JAX then locks the folder around each read and write (``filelock``), so no process
    loads an entry another is still writing, and evicts the least recently used entries beyond
    ``max_bytes``. Its eviction reads an access-time file beside every entry; entries written
    without a limit (by an earlier version) have none, and every later write would fail. So once
    per folder each such entry gets one (its modification time), and a mark file records it."""
    folder = jax.config.jax_compilation_cache_dir
    if folder and os.path.isdir(folder) and not os.path.exists(os.path.join(folder, _LOCKED_MARK)):
        try:
            for entry in Path(folder).glob("*-cache"):
                stamp = entry.with_name(entry.name[:-len("-cache")] + "-atime")
                if not stamp.exists():
                    write_atomically(stamp, entry.stat().st_mtime_ns.to_bytes(8, "little"))
            write_atomically(Path(folder) / _LOCKED_MARK, b"entries carry access times\n")
        except OSError:
            pass  # a read-only cache: JAX warns on its own writes
    jax.config.update("jax_compilation_cache_max_size", max_bytes)


def _avals(args):
    return jax.tree_util.tree_map(lambda a: jax.ShapeDtypeStruct(np.shape(a), jax.numpy.result_type(a)), args)


def write_atomically(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder renamed into place
    (a reader sees the old file or the new one, never half of one)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


class Program:
    """One program: ``fn(*args)`` for arguments shaped like ``example`` (a tuple of array
    pytrees), keyed by ``structure`` (a string naming everything the code depends on besides
    the arguments' shapes). :meth:`start` exports and begins compiling it; calling it waits
    for the compiled executable."""

    def __init__(self, name: str, fn: Callable, example: tuple, structure: str, preset: str = "optimized",
                 pool: Optional[concurrent.futures.Executor] = None, packed: bool = False):
        self.name = name
        #: the compiled program returns its outputs packed into one float64 vector (:meth:`unpack_calls`)
        self.packed = packed
        self._out = None
        self.fn = fn
        self.avals = _avals(tuple(example))
        self.preset = preset
        self.pool = pool
        leaves = jax.tree_util.tree_flatten(self.avals)
        shapes = repr([(a.shape, str(a.dtype)) for a in leaves[0]]) + repr(leaves[1])
        text = "\n".join([name, structure, preset, shapes, code_version(), jax.__version__, str(packed),
                          str(jax.config.jax_enable_x64)])
        self.key = hashlib.sha256(text.encode()).hexdigest()[:40]
        self._future: Optional[concurrent.futures.Future] = None
        self._compiled = None
        self._exported_module = None
        #: the module came from the cache folder (not traced); seconds to trace or load it, and
        #: to compile it (or load it from the XLA cache)
        self.loaded_from_disk = False
        self.export_seconds: Optional[float] = None
        self.compile_seconds: Optional[float] = None
        #: the executable came from the cache folder (:func:`_load_executable`), not from XLA
        self.executable_loaded = False
        #: operations in the traced module (StableHLO, before XLA's passes), when traced here
        self.operations: Optional[int] = None
        #: the program needs a derivative JAX lacks (its trace raised NotImplementedError)
        self.unsupported = False
        BUILT.append(self)

    def _exported(self) -> "jax.export.Exported":
        t0 = time.perf_counter()
        try:
            return self._export_or_load()
        finally:
            self.export_seconds = time.perf_counter() - t0

    def _export_or_load(self) -> "jax.export.Exported":
        folder = cache_folder()
        path = None if folder is None else folder / f"{self.name}-{self.key}.jaxexport"
        unsupported = None if path is None else path.with_suffix(".unsupported")
        if unsupported is not None and unsupported.exists():
            # an earlier trace of this program met a derivative JAX lacks: say so again at once
            self.unsupported = True
            raise NotImplementedError(unsupported.read_text(errors="replace"))
        if path is not None and path.exists():
            try:
                exported = jax.export.deserialize(bytearray(path.read_bytes()))
                self.loaded_from_disk = True
                return exported
            except Exception:  # noqa: BLE001 - an unreadable file is traced again and replaced
                pass
        with _LOCK:
            TRACES[self.name] = TRACES.get(self.name, 0) + 1
        fn = self.fn
        named = _named(fn, self.name)
        try:
            with _without_locations():
                exported = jax.export.export(jax.jit(named))(*self.avals)
        except NotImplementedError as exc:
            self.unsupported = True
            if unsupported is not None:
                try:
                    write_atomically(unsupported, str(exc).encode())
                except OSError:
                    pass
            raise
        if os.environ.get(LOG_VARIABLE):
            self.operations = exported.mlir_module().count("stablehlo.")
        if path is not None:
            try:
                write_atomically(path, exported.serialize())
            except OSError:
                pass  # a read-only cache still runs, tracing again next time
        return exported

    def _prepare(self, exported):
        """What compiling ``exported`` needs from this thread: the stored executable's path when
        one may be loaded, else the module lowered for XLA. Lowering holds Python's lock, so it
        is done here, in the thread that traces, and the pool gets only XLA's compilation, which
        runs without the lock: a program's compilation then starts as soon as it is traced
        instead of waiting for the lock behind the tracing of the next program."""
        t0 = time.perf_counter()
        self._out = (exported.out_tree, [(tuple(a.shape), np.dtype(a.dtype)) for a in exported.out_avals])
        trees = self._trees(exported)
        path = self._executable_path(exported) if _runtime_ready(exported) else None
        lowered = self._lower(exported, path is not None) if path is None or not path.exists() else None
        return trees, path, lowered, time.perf_counter() - t0

    def _lower(self, exported, stored: bool):
        """(``exported`` lowered for XLA with the preset's options, those options); a program
        whose executable is ``stored`` is named ``diffsense_NAME`` (module docstring)."""
        name = f"diffsense_{self.name}" if stored else self.name
        call = _named(_packing(exported.call) if self.packed else exported.call, name)
        opts = compiler_options(self.preset)
        jitted = jax.jit(call, compiler_options=opts) if opts else jax.jit(call)
        return jitted.lower(*self.avals), opts

    def _compile(self, prepared):
        trees, path, lowered, seconds = prepared
        t0 = time.perf_counter()
        with _LOCK:
            COMPILATIONS[self.name] = COMPILATIONS.get(self.name, 0) + 1
        # the options the preset asks for: an executable is stored only when XLA accepted them
        compiled = None if lowered is not None else _load_executable(path, trees, preset_options(self.preset))
        self.executable_loaded = compiled is not None
        if compiled is None:
            if lowered is None:  # a stored executable that cannot be loaded: compile again
                lowered = self._lower(self._exported_module, path is not None)
            module, opts = lowered
            _HITS.count = 0
            compiled = module.compile()
            # an executable JAX read from its own persistent cache serialises without the
            # kernels XLA's CPU backend built for it (loading that copy fails at run time):
            # only a fresh compilation is kept
            if path is not None and not _HITS.count and opts == preset_options(self.preset):
                _store_executable(path, compiled, trees)
        self.compile_seconds = seconds + time.perf_counter() - t0
        return compiled

    def _trees(self, exported):
        """(input tree, output tree) of the compiled program: its arguments and no keywords; one
        packed vector or the exported function's outputs."""
        out = jax.tree_util.tree_structure(0.0) if self.packed else exported.out_tree
        return jax.tree_util.tree_structure((self.avals, {})), out

    def _executable_path(self, exported) -> Optional[Path]:
        """``<cache>/programs/NAME-HASH.xlaexec``: the compiled executable of ``exported``, keyed
        by the module's content (its serialised StableHLO, whether its outputs are packed) and
        everything the machine code depends on besides (XLA options of the preset, jaxlib,
        platform and device kind, ``XLA_FLAGS``); None without a cache folder."""
        folder = cache_folder()
        if folder is None:
            return None
        device = jax.devices()[0]
        module = hashlib.sha256(exported.mlir_module_serialized).hexdigest()
        text = "\n".join([self.name, module, f"packed={self.packed}", repr(preset_options(self.preset)),
                          _jaxlib_version(), device.platform, device.device_kind, str(jax.device_count()),
                          os.environ.get("XLA_FLAGS", "")])
        return folder / f"{self.name}-{hashlib.sha256(text.encode()).hexdigest()[:40]}.xlaexec"

    def start(self) -> "Program":
        """Export (trace, or load from disk) in this thread and compile in the pool (or here,
        without one). Idempotent."""
        if self._future is None and self._compiled is None:
            self._exported_module = exported = self._exported()
            prepared = self._prepare(exported)
            if self.pool is None:
                self._compiled = self._compile(prepared)
            else:
                self._future = self.pool.submit(self._compile, prepared)
        return self

    def compiled(self):
        """The compiled executable (waits for its compilation)."""
        if self._compiled is None:
            self.start()
            if self._compiled is None:
                self._compiled = self._future.result()
        return self._compiled

    @property
    def ready(self) -> bool:
        return self._compiled is not None or (self._future is not None and self._future.done())

    def __call__(self, *args):
        return self.compiled()(*args)

    def unpack_calls(self, flats):
        """The outputs (NumPy pytree) of several calls of a packed program whose outputs all lead
        with the same row axis, from their results ``flats`` (k, length) on the host, joined
        along that axis (call after call): one transfer per call instead of one per output array
        (a design's evaluation has hundreds), and one slice per output for all the calls.

        >>> p = Program("demo", lambda v: {"a": v * 2.0, "b": v[:, :1] > 0.0}, (np.zeros((2, 3)),), "demo",
        ...             packed=True)
        >>> out = p.unpack_calls(np.stack([p(np.ones((2, 3))), p(-np.ones((2, 3)))]))
        >>> out["a"].shape, out["b"][:, 0].tolist()
        ((4, 3), [True, True, False, False])
        """
        if not self.packed:
            raise ValueError(f"program {self.name}: unpack_calls needs a packed program")
        self.compiled()
        tree, leaves = self._out
        flats = np.asarray(flats)
        k = flats.shape[0]
        out, start = [], 0
        for shape, dtype in leaves:
            size = int(np.prod(shape, dtype=np.int64))
            block = flats[:, start:start + size].reshape((k * shape[0],) + tuple(shape[1:]))
            out.append(block.astype(dtype, copy=False))
            start += size
        return jax.tree_util.tree_unflatten(tree, out)


def _packing(call):
    """``call`` with its outputs raveled and concatenated into one float64 vector (booleans and
    integers are exact in float64; :meth:`Program.unpack_calls` restores the arrays). Float64 leaves
    enter as they are (lax operations, no promotion): a program traced here may have weakly
    typed outputs where the same program loaded from disk has not, and a conversion emitted for
    one and not the other would make the two compilations differ (a persistent-cache miss)."""
    def packed(*args):
        flat = [jax.lax.reshape(a if a.dtype == np.float64 else jax.lax.convert_element_type(a, np.float64),
                                (int(np.prod(a.shape, dtype=np.int64)),))
                for a in jax.tree_util.tree_leaves(call(*args))]
        return jax.lax.concatenate(flat, 0) if flat else jax.numpy.zeros((0,))
    return packed


#: persistent-cache hits of JAX in the current thread (JAX's monitoring events)
_HITS = threading.local()


def _count_cache_hits(event: str, **kwargs) -> None:
    if event == "/jax/compilation_cache/cache_hits":
        _HITS.count = getattr(_HITS, "count", 0) + 1


jax.monitoring.register_event_listener(_count_cache_hits)


def _jaxlib_version() -> str:
    try:
        import jaxlib

        return jaxlib.__version__
    except (ImportError, AttributeError):
        return ""


def _runtime_ready(exported) -> bool:
    """Whether an executable of ``exported`` may be stored and loaded directly: true when the
    module calls no custom kernels, or only LAPACK's, whose entry points are set up here first
    (lowering a module sets them up; loading an executable does not, and a LAPACK call then
    jumps to an empty pointer). A module with other custom calls is always compiled through
    JAX (and its persistent cache)."""
    module = exported.mlir_module_serialized
    if b"custom_call" not in module:
        return True
    targets = set(re.findall(r"custom_call @([A-Za-z0-9_.]+)", exported.mlir_module()))
    if not targets or not all(t.startswith("lapack_") for t in targets):
        return False
    try:
        from jax._src.lax.linalg import initialize_lapack

        initialize_lapack()
    except Exception:  # noqa: BLE001 - a JAX without this entry point: compile as usual
        return False
    return True


def _load_executable(path: Path, trees, options: dict):
    """The executable stored at ``path`` (:func:`_store_executable`), compiled with the XLA
    options ``options``, or None when there is none or it cannot be loaded (then it is compiled
    again and the file replaced). Loading it skips the lowering of the exported module and
    JAX's persistent-cache lookup (hashing the module), about a third of a second for the
    solver's program. The file is trusted as JAX's own persistent cache is: it is machine code
    this package wrote into the user's cache folder."""
    import io

    from jax._src import compiler
    from jax.experimental import serialize_executable

    try:
        data = path.read_bytes()
    except OSError:
        return None
    try:
        backend = jax.devices()[0].client
        devices = backend.devices()[:1]
        compile_options = compiler.get_compile_options(
            num_replicas=1, num_partitions=1, env_options_overrides=options or None, backend=backend)

        class _Unpickler(serialize_executable._JaxPjrtUnpickler):
            # the executable is deserialised with the options it was compiled with, as JAX's
            # persistent cache does: the CPU backend rebuilds its kernels from them
            def persistent_load(self, pid):
                if pid[0] == "exec":
                    return self.backend.deserialize_executable(pid[1], self.execution_devices, compile_options)
                return super().persistent_load(pid)

        unloaded, args_info_flat, no_kwargs = _Unpickler(io.BytesIO(data), backend, devices).load()
        in_tree, out_tree = trees
        return jax.stages.Compiled(unloaded.load(), [], in_tree.unflatten(args_info_flat), out_tree,
                                   no_kwargs=no_kwargs)
    except Exception:  # noqa: BLE001 - a stale or damaged file is compiled again
        return None


def _store_executable(path: Path, compiled, trees) -> None:
    """Keep ``compiled`` at ``path`` (written atomically) when its argument and output trees are
    those :meth:`Program._trees` will rebuild on loading; a read-only cache is skipped."""
    from jax.experimental import serialize_executable

    try:
        data, in_tree, out_tree = serialize_executable.serialize(compiled)
    except Exception:  # noqa: BLE001 - a backend that cannot serialise compiles each time
        return
    if (in_tree, out_tree) != tuple(trees):
        return
    try:
        write_atomically(path, data)
    except OSError:
        pass


class LazyProgram:
    """A :class:`Program` whose example arguments are those of its first call (for callers that
    learn the shapes only then); same keying, disk cache and compilation."""

    def __init__(self, name: str, fn: Callable, structure: str, preset: str = "optimized"):
        self.name, self.fn, self.structure, self.preset = name, fn, structure, preset
        self._programs: Dict[str, Program] = {}

    def __call__(self, *args):
        shapes = repr(jax.tree_util.tree_map(lambda a: (np.shape(a), str(np.asarray(a).dtype)), args))
        if shapes not in self._programs:
            self._programs[shapes] = Program(self.name, self.fn, args, self.structure, self.preset)
        return self._programs[shapes](*args)


def _without_locations():
    """A context in which JAX lowers without source locations (file and line of each operation),
    so that a module's bytes depend on its computation only; a no-op on a JAX without the
    setting."""
    try:
        from jax._src import config as jax_config

        return jax_config.traceback_in_locations_limit(0)
    except (ImportError, AttributeError, TypeError):
        return contextlib.nullcontext()


def _named(fn, name: str):
    """``fn`` under the name ``name`` (what JAX's compilation log and profiles show)."""
    def program(*args):
        return fn(*args)
    program.__name__ = program.__qualname__ = name.replace("-", "_")
    return program


def report_programs() -> str:
    """One line per program built in this process: name, traced or loaded from the cache folder,
    seconds to trace (or load) and to compile (or load from XLA's cache), operations traced."""
    lines = []
    for p in BUILT:
        how = ("unsupported" if p.unsupported else "loaded" if p.loaded_from_disk
               else "traced" if p.export_seconds is not None else "unused")
        lines.append(f"program {p.name} {how} export_s={p.export_seconds or 0:.2f} "
                     f"compile_s={p.compile_seconds or 0:.2f} ops={p.operations if p.operations is not None else '-'}")
    return "\n".join(lines)


def _report_at_exit() -> None:
    if os.environ.get(LOG_VARIABLE) and BUILT:
        import sys

        print(report_programs(), file=sys.stderr)


atexit.register(_report_at_exit)

# the solvers' result types travel in and out of compiled programs
for _cls in (Result, KKTResidual, Conflict, Scales):
    register_serializable(_cls)

_POOL: Optional[concurrent.futures.ThreadPoolExecutor] = None


def compile_pool() -> concurrent.futures.ThreadPoolExecutor:
    """The process's pool of compiling threads (two: the machines this runs on have a few
    cores, and XLA's compilation of one module is mostly one thread)."""
    global _POOL
    if _POOL is None:
        _POOL = concurrent.futures.ThreadPoolExecutor(max_workers=2, thread_name_prefix="diffsense-compile")
    return _POOL


def finish_compiling() -> None:
    """Wait for every compilation started in the pool of :func:`compile_pool` (its programs are
    stored in the cache folder as they finish), as an interpreter's exit would, and close the
    pool; a later :func:`compile_pool` starts a new one."""
    global _POOL
    pool, _POOL = _POOL, None
    if pool is not None:
        pool.shutdown(wait=True)


__all__ = ["Program", "LazyProgram", "register_serializable", "write_atomically", "lock_compilation_cache",
           "CACHE_MAX_BYTES", "code_version", "cache_folder", "compile_pool", "finish_compiling", "report_programs",
           "COMPILATIONS", "TRACES", "LOG_VARIABLE"]

