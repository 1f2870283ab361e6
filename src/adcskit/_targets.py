"""One kernel source, three compile targets: numba's CPU per sample, CPU lane blocks, and CUDA.

The pattern
-----------
A batched simulation (many independent samples, a scalar state per sample, no
communication) is written **once**, as a plain per-sample Python function::

    def _sample(i, A):
        # simulate sample i: read A.P[i, :], loop over time, write A.OUT[i, :]
        ...

Rules for that function (so that both numba targets accept it and compute the same
floating-point operations in the same order):

* scalars, ``math`` functions, indexing of the arrays it receives, ``range`` loops only;
  no allocation (``np.zeros``...), no ``prange``, no NumPy calls, no Python objects;
* any per-sample scratch memory (a delay line, a small state vector) is *passed in* by the
  driver as rows of arrays allocated on the host (or, on the GPU, ``cuda.local.array(L,
  dtype)`` with a compile-time length ``L``);
* results are written to ``out[i, ...]`` (one row per sample);
* never a ctypes function (numba's in-kernel ``get_num_threads`` is one) or another dynamic
  global: numba then refuses to cache the kernel on disk and every process recompiles it.

A kernel with many arrays declares them once, as a table (``ARGS`` of
:mod:`adcskit.simulation._kernels` and :mod:`adcskit.simulation._wheel_kernels`), and passes
them as one named tuple built from it (numba passes a named tuple of arrays as one argument,
on both targets; :func:`launch_chunked`'s ``pack``).

It is wrapped in :class:`PerSample`, which compiles it with ``numba.njit`` for the CPU and
— only when asked — with ``numba.cuda.jit(device=True)`` for the GPU. The drivers, one per
target:

* **CPU, per sample**: a compiled driver calls ``SAMPLE.cpu(i, ...)`` for each sample, in
  a ``numba.prange`` loop (the on-off loop with traces, :mod:`adcskit.control._onoff_kernels`)
  or serially in a compiled block driver that a thread pool runs on numba's threads (the wheel
  loop, :func:`adcskit.simulation._wheel_kernels.run_wheels`: the same parallelism, a fraction
  of a ``prange`` driver's compile time);
* **CPU, lane blocks**: a ``prange`` over blocks of up to ``LANES`` samples that advances
  the block's samples together: at each step a pass over the lanes runs each sample's step
  functions, then the state the compiler should vectorise (the rigid body's RK4 step) is
  advanced in one loop over the lanes. That state lives on the block function's stack
  (:func:`adcskit._stack.stack_f64`: LLVM vectorises a loop over stack arrays, not over
  argument arrays it cannot prove distinct); a lane's other scalars live between the passes
  in the block's rows, at offsets declared once with :func:`lane_slots`; the block size comes
  from :func:`lane_block_size` (computed in Python and passed in). The same operations in the
  same order per sample as the per-sample function, so the numbers are the same bit for bit.
  Users: the thruster closed loop (:func:`adcskit.simulation._kernels.block_loop`, whose step
  functions are the per-sample loop's own: tested bit for bit against it by
  tests/simulation/test_lanes.py) and the on-off loop without traces
  (:func:`adcskit.control._onoff_kernels._lanes`, a second source tested against ``_sample``);
  the wheel loop does not use it yet;
* **GPU**: a ``cuda.jit`` kernel built by a factory on first use (cached by
  :class:`LazyKernels`, keyed by its compile-time constants such as ``L``) that does
  ``i = cuda.grid(1); if i < n: _SAMPLE.cuda()(i, ...)``, launched in chunks by
  :func:`launch_chunked`.

``numba.cuda`` is imported only inside :func:`import_cuda`, so CPU-only users never load it.
The kernel factory binds it to a *module global* named ``cuda`` of the kernel module
(``global cuda; cuda = import_cuda()``) and the kernel body refers to that global, not to a
local of the factory: numba's CUDA simulator swaps module globals that are the ``cuda``
module for its fake one, and would not see a closure variable.
The backend names are ``"cpu"``, ``"cuda"`` and ``"auto"`` (:func:`resolve_backend`):
``"auto"`` is CUDA when a real device is usable (never the CUDA simulator) and the CPU
otherwise; an explicit ``"cuda"`` without numba-cuda or without a visible device raises
:class:`adcskit.errors.SolverError` naming the ``gpu`` extra. With
``NUMBA_ENABLE_CUDASIM=1`` set *before* numba is imported, an explicit ``"cuda"`` runs the
GPU driver in numba's CUDA simulator (pure Python, slow: for tests of a handful of short
samples).

Helpers that a per-sample function calls (a quaternion product, the Schmitt trigger) are
declared with :func:`device`: a plain function that numba compiles into whichever kernel calls
it, on either target (numba's generic-target ``register_jitable``), and that stays a plain
Python function for the reference paths. Shared helpers live once, next to the model they
belong to (:mod:`adcskit.attitude._device`, :mod:`adcskit.control._actuator`).

Users (each with a CPU and a GPU driver; the GPU ones tested bit for bit against the CPU
ones under the CUDA simulator and compiled to PTX for sm_90 by ``tests/test_cuda_ptx.py``):

* :mod:`adcskit.control._onoff_kernels` (the on-off loop);
* :mod:`adcskit.simulation._wheel_kernels` (the wheel / magnetorquer simulator): its
  per-sample scratch rows stay global arrays passed in by the driver, as on the CPU; its
  per-sample function is a sequence of step functions (sensors, modes, control, environment
  torques, RK4, knowledge, metrics);
* :mod:`adcskit.simulation._kernels` (the thruster closed-loop simulator; lane blocks on the
  CPU): its loop calls the
  MEKF steps and the gyro model through CPU-only ``njit`` dispatchers (compiled once, cached
  on disk); the CUDA compilation rebinds those names to the device sources they were built
  from (``PerSample(device_names=...)``, the same code object with other globals), and the
  Wahba / min-max solvers, numba kernels with NumPy linear algebra that the device compiler
  cannot take, to stand-ins the GPU driver never reaches (``simulate`` refuses those
  estimators with ``backend="cuda"``).

Compiling a device function without a GPU (``numba.cuda.compile_ptx``) needs numba-cuda (the
``gpu`` extra): numba's own deprecated ``numba.cuda`` target cannot type ``max(a, b)`` for
the device in numba 0.68.

Hand-written here: only the thin compile/dispatch helper and the chunked launch loop that every
GPU driver shares (:func:`launch_chunked`); the compilers are numba's.
"""

from __future__ import annotations

import threading
import types
from collections import namedtuple
from collections.abc import Callable
from typing import Any

import numba
import numpy as np

from adcskit.errors import InputError, InputTypeError, SolverError

__all__ = [
    "TARGET_BACKENDS",
    "GPU_EXTRA_HINT",
    "PerSample",
    "LazyKernels",
    "device",
    "rebound",
    "import_cuda",
    "cuda_status",
    "cuda_usable",
    "simulator_enabled",
    "resolve_backend",
    "launch_chunked",
    "lane_slots",
    "lane_block_size",
]

TARGET_BACKENDS = ("cpu", "cuda", "auto")

GPU_EXTRA_HINT = (
    "install the GPU extra (pip install 'adcskit[gpu]', which brings numba-cuda and the CUDA "
    "runtime wheels) on a machine with an NVIDIA GPU and driver"
)


def simulator_enabled() -> bool:
    """True when numba's CUDA simulator is on (``NUMBA_ENABLE_CUDASIM=1`` at import).

    Examples
    --------
    >>> isinstance(simulator_enabled(), bool)
    True
    """
    return bool(getattr(numba.config, "ENABLE_CUDASIM", 0))


def import_cuda() -> Any:
    """Import and return ``numba.cuda`` (numba-cuda when installed, else numba's built-in).

    Raises
    ------
    SolverError
        If no CUDA target can be imported; the message names the ``gpu`` extra.

    Examples
    --------
    >>> try:
    ...     cuda = import_cuda()
    ... except SolverError as exc:
    ...     assert "adcskit[gpu]" in str(exc)
    """
    try:
        from numba import cuda
    except Exception as exc:  # ImportError, or a CUDA binding that fails to load
        raise SolverError(f"backend='cuda' needs numba's CUDA target, which failed to import "
                          f"({type(exc).__name__}: {exc}); {GPU_EXTRA_HINT}") from exc
    return cuda


def cuda_status() -> tuple[bool, str]:
    """Whether a CUDA device (or the simulator) can run kernels, and why not.

    Returns
    -------
    (bool, str)
        ``(True, description)`` when kernels can run, ``(False, reason)`` otherwise.

    Examples
    --------
    >>> ok, why = cuda_status()
    >>> isinstance(ok, bool) and isinstance(why, str)
    True
    """
    try:
        cuda = import_cuda()
    except SolverError as exc:
        return False, str(exc)
    if simulator_enabled():
        return True, "numba CUDA simulator (NUMBA_ENABLE_CUDASIM=1)"
    try:
        ok = bool(cuda.is_available())
    except Exception as exc:  # driver library present but broken
        return False, f"the CUDA driver could not be queried ({type(exc).__name__}: {exc})"
    if not ok:
        return False, "no CUDA device is visible (numba.cuda.is_available() is False)"
    try:
        name = cuda.get_current_device().name
        name = name.decode() if isinstance(name, bytes) else str(name)
    except Exception as exc:
        return False, f"the CUDA device could not be opened ({type(exc).__name__}: {exc})"
    return True, name


def cuda_usable() -> bool:
    """True when a *real* CUDA device can run kernels (the simulator does not count).

    Examples
    --------
    >>> cuda_usable() in (True, False)
    True
    """
    return not simulator_enabled() and cuda_status()[0]


def resolve_backend(backend: str, *, name: str = "backend") -> str:
    """Map ``"cpu" | "cuda" | "auto"`` to the target that will run: ``"cpu"`` or ``"cuda"``.

    Parameters
    ----------
    backend : {"cpu", "cuda", "auto"}
        ``"auto"`` picks CUDA when a real device is usable, else the CPU.
    name : str
        Parameter name used in error messages.

    Returns
    -------
    str
        ``"cpu"`` or ``"cuda"``.

    Raises
    ------
    InputError
        Unknown backend name.
    SolverError
        ``"cuda"`` requested but numba-cuda is missing or no device is visible.

    Examples
    --------
    >>> resolve_backend("cpu")
    'cpu'
    >>> resolve_backend("auto") in ("cpu", "cuda")
    True
    """
    if backend not in TARGET_BACKENDS:
        raise InputError(f"{name} must be one of {', '.join(map(repr, TARGET_BACKENDS))}; got {backend!r}")
    if backend == "cpu":
        return "cpu"
    if backend == "auto":
        return "cuda" if cuda_usable() else "cpu"
    ok, why = cuda_status()
    if not ok:
        if "gpu" in why and "extra" in why:
            raise SolverError(why)
        raise SolverError(f"{name}='cuda' cannot run: {why}; {GPU_EXTRA_HINT}, or use {name}='cpu' "
                          f"or {name}='auto'")
    return "cuda"


class PerSample:
    """A plain per-sample function compiled for the CPU now and for CUDA on first use.

    Parameters
    ----------
    fn : callable
        The per-sample function (see the module docstring for its rules).
    cache : bool
        Cache the CPU compilation on disk (numba ``cache=True``).
    inline : {"always", "never"}
        numba's inlining of the CPU compilation into its callers. ``"always"`` (default)
        gives the drivers the single-thread speed of a hand-inlined loop; ``"never"`` keeps a
        long per-sample function (the closed-loop simulator's) one compiled function, which
        compiles several times faster and computes the same numbers.
    error_model : {"python", "numpy"}
        numba's ``error_model`` of the CPU compilation: ``"numpy"`` drops the zero-divisor
        check (and its exception branch) of every division; a kernel that never divides by
        zero computes the same numbers either way (the CUDA target never checks).
    nrt : bool
        numba's reference-counting runtime in the CPU compilation (numba's ``_nrt`` option,
        inherited by the ``register_jitable`` / :func:`device` helpers that it compiles).
        ``False`` drops the reference-count updates (an atomic add, a call each) at every
        array view and at the entry and exit of every helper that receives arrays; only for
        a function that allocates nothing (numba then refuses to compile an allocation).
    device_names : dict of str to callable, optional
        Module globals of ``fn`` rebound for the CUDA compilation only: a name that the CPU
        compilation resolves to a CPU-only ``numba.njit`` dispatcher (compiled once and
        cached on disk, called rather than inlined) is bound to a device-compilable function
        of the same source (its :func:`device` / ``register_jitable`` original) or to a
        device stand-in for a branch the GPU driver refuses to take. The CUDA compilation
        is of the same code object with these globals replaced; the CPU compilation is
        untouched.

    Attributes
    ----------
    py : callable
        The plain Python function (reference; slow).
    cpu : numba dispatcher
        ``numba.njit(inline=inline)`` compilation, called by the njit drivers.

    Examples
    --------
    >>> import numpy as np
    >>> def twice(i, x, out):
    ...     out[i] = 2.0 * x[i]
    >>> ps = PerSample(twice, cache=False)
    >>> out = np.zeros(2)
    >>> ps.cpu(1, np.array([1.0, 3.0]), out)
    >>> float(out[1])
    6.0
    """

    def __init__(self, fn: Callable[..., Any], *, cache: bool = True, inline: str = "always",
                 error_model: str = "python", nrt: bool = True,
                 device_names: dict[str, Any] | None = None) -> None:
        if inline not in ("always", "never"):
            raise InputError(f"inline must be 'always' or 'never'; got {inline!r}")
        if error_model not in ("python", "numpy"):
            raise InputError(f"error_model must be 'python' or 'numpy'; got {error_model!r}")
        if not isinstance(nrt, bool):
            raise InputTypeError(f"nrt must be True or False; got {nrt!r}")
        self.py = fn
        self.cpu = numba.njit(cache=cache, nogil=True, inline=inline, error_model=error_model,
                              _nrt=nrt)(fn)
        self.device_names = dict(device_names or {})
        unknown = sorted(set(self.device_names) - set(fn.__code__.co_names))
        if unknown:
            raise InputError(f"device_names must name globals that {fn.__name__} uses; got {unknown}")
        self._cuda: Any = None
        self._lock = threading.Lock()

    def device_source(self) -> Callable[..., Any]:
        """The plain function that the CUDA target compiles: ``fn`` itself, or ``fn``'s code
        with :attr:`device_names` rebound in a copy of its module globals."""
        if not self.device_names:
            return self.py
        return rebound(self.py, self.device_names)

    def cuda(self) -> Any:
        """The ``numba.cuda.jit(device=True)`` compilation (imports numba.cuda)."""
        with self._lock:
            if self._cuda is None:
                self._cuda = import_cuda().jit(device=True)(self.device_source())
            return self._cuda


def launch_chunked(kernel: Any, args: dict[str, Any], names: tuple[str, ...], *, n: int, chunk: int,
                   threads: int, shared: frozenset[str] | set[str] = frozenset(),
                   outputs: tuple[str, ...] = (), pack: Callable[..., Any] | None = None) -> None:
    """Run a one-thread-per-sample CUDA ``kernel`` over ``n`` samples in chunks of ``chunk``.

    ``args`` maps each of ``names`` (the kernel's parameters, in order) to a host array. The
    ``shared`` ones are copied to the device once; every other array has one row per sample and
    goes in row slices ``[lo:hi]`` per chunk. After each launch the ``outputs`` slices are copied
    back into their host arrays in place. Zero-size arrays become empty device arrays of the same
    shape. With ``pack`` (e.g. a named-tuple class) the kernel gets one argument,
    ``pack(*arrays)``, instead of the arrays as separate arguments. This is the chunk loop of every GPU driver (:mod:`adcskit.simulation._kernels`,
    :mod:`adcskit.simulation._wheel_kernels`).
    """
    cuda = import_cuda()

    def put(a: Any) -> Any:
        a = np.ascontiguousarray(a)
        return cuda.to_device(a) if a.size else cuda.device_array(a.shape, a.dtype)

    on_device = {a: put(args[a]) for a in shared}
    for lo in range(0, n, chunk):
        hi = min(n, lo + chunk)
        dev = {a: on_device[a] if a in on_device else put(args[a][lo:hi]) for a in names}
        dev_args = tuple(dev[a] for a in names)
        launch = kernel[(hi - lo + threads - 1) // threads, threads]
        if pack is None:
            launch(*dev_args)
        else:
            launch(pack(*dev_args))
        for a in outputs:
            args[a][lo:hi] = dev[a].copy_to_host()


def rebound(fn: Callable[..., Any], names: dict[str, Any]) -> Callable[..., Any]:
    """A copy of ``fn`` whose module globals ``names`` are rebound (``fn`` is unchanged).

    How a per-sample function or a step function it calls gets its CUDA build
    (:attr:`PerSample.device_names`): the same code object, with the names that the CPU
    build resolves to CPU-only dispatchers bound to device-compilable functions.

    Parameters
    ----------
    fn : callable
        A plain Python function.
    names : dict of str to object
        Global names of ``fn`` and what they are bound to in the copy.

    Returns
    -------
    callable
        The copy (same code, name, qualified name and docstring).

    Examples
    --------
    >>> def twice(x):
    ...     return scale * x
    >>> scale = 2.0
    >>> thrice = rebound(twice, {"scale": 3.0})
    >>> twice(1.0), thrice(1.0)
    (2.0, 3.0)
    """
    g = dict(fn.__globals__)
    g.update(names)
    dev = types.FunctionType(fn.__code__, g, fn.__name__, fn.__defaults__, fn.__closure__)
    dev.__qualname__ = fn.__qualname__
    dev.__doc__ = fn.__doc__
    return dev


def device(fn: Callable[..., Any] | None = None, *, inline: str = "never") -> Any:
    """Declare a device helper: a plain function callable from per-sample kernels on both targets.

    The function is returned unchanged (plain Python calls it as Python: the reference
    paths), and registered with numba's generic target (``numba.extending.register_jitable``)
    so that code compiled by ``numba.njit`` or ``numba.cuda.jit`` compiles it into the caller.
    The same rules as for a per-sample function hold (see the module docstring).

    Parameters
    ----------
    fn : callable, optional
        The helper; without it, ``device(inline=...)`` returns the decorator.
    inline : {"never", "always"}
        numba's inlining into the caller (LLVM may still inline a small helper). Either
        choice computes the same floating-point operations in the same order. ``"always"`` is
        numba's inlining of a typed overload, which types the helper on its own first: for a
        large CPU-only helper ``numba.njit(inline="always")`` (untyped IR inlining) compiles
        faster (docs/benchmarks.md, "Kernel plumbing (issue 41)").

    Returns
    -------
    callable
        ``fn`` itself (or the decorator).

    Examples
    --------
    >>> import numba
    >>> @device
    ... def half(x):
    ...     return 0.5 * x
    >>> @numba.njit(cache=False)
    ... def quarter(x):
    ...     return half(half(x))
    >>> half(3.0), quarter(3.0)
    (1.5, 0.75)
    """
    if inline not in ("always", "never"):
        raise InputError(f"inline must be 'always' or 'never'; got {inline!r}")
    from numba.extending import register_jitable

    wrap = register_jitable(inline=inline)
    return wrap if fn is None else wrap(fn)


class LazyKernels:
    """CUDA kernels built by ``factory(*key)`` on first use and cached by ``key``.

    The key holds the kernel's compile-time constants (e.g. the length of a per-thread
    ``cuda.local.array``), so each distinct value compiles once per process.

    Examples
    --------
    >>> kernels = LazyKernels(lambda n: [0.0] * n)
    >>> kernels.get(3) is kernels.get(3)
    True
    """

    def __init__(self, factory: Callable[..., Any]) -> None:
        self._factory = factory
        self._cache: dict[tuple, Any] = {}
        self._lock = threading.Lock()

    def get(self, *key: Any) -> Any:
        with self._lock:
            if key not in self._cache:
                self._cache[key] = self._factory(*key)
            return self._cache[key]


def lane_slots(name: str, **widths: int) -> tuple[Any, int]:
    """Offsets of consecutive slots of the given widths in a lane block's row, and the row's
    width: one line ``NAME=width`` per per-lane variable (the lane-block target, module
    docstring). The offsets are a named tuple (``name``) that numba freezes as constants when a
    kernel reads it as a module global (``FS[l, _F.NAME + k]``).

    Examples
    --------
    >>> slots, width = lane_slots("Slots", rate=3, prop=1, err=4)
    >>> slots.rate, slots.prop, slots.err, width
    (0, 3, 4, 8)
    """
    offsets, o = [], 0
    for key, w in widths.items():
        if not isinstance(w, int) or isinstance(w, bool) or w < 1:
            raise InputError(f"lane_slots width of {key} must be a positive integer; got {w!r}")
        offsets.append(o)
        o += w
    return namedtuple(name, list(widths))(*offsets), o


def _busiest(n: int, size: int, threads: int) -> int:
    """Samples on the busiest thread when ``n`` samples run in blocks of ``size`` on ``threads``
    threads: ``prange`` gives each thread a contiguous run of ``ceil(blocks / threads)`` blocks
    at most."""
    return min(n, ((n + size - 1) // size + threads - 1) // threads * size)


def lane_block_size(n: int, threads: int, lanes: int) -> int:
    """Samples per lane block for ``n`` samples on ``threads`` threads, blocks of at most
    ``lanes``.

    ``lanes`` (a full vector loop) unless whole blocks would load the busiest thread
    (:func:`_busiest`) more than 5/4 of an even share: ``n = 64`` on 16 threads in blocks of 8
    makes 8 blocks and leaves 8 threads idle, ``n = 24`` on 2 makes 3 blocks (16 samples on one
    thread). Then the size (at most ``lanes``, the largest on a tie) that minimises the busiest
    thread's samples: 4 (16 blocks) and 6 (4 blocks) in those examples. Blocks of fewer than
    ``lanes`` samples run their vector loops partly scalar; a lane-block kernel's results do not
    depend on the size.

    Examples
    --------
    >>> lane_block_size(64, 16, 8), lane_block_size(24, 2, 8), lane_block_size(64, 2, 8)
    (4, 6, 8)
    """
    if n < 1:
        return 1
    if threads <= 1 or 4 * _busiest(n, lanes, threads) * threads <= 5 * n:
        return lanes
    best = lanes
    for size in range(lanes - 1, 0, -1):
        if _busiest(n, size, threads) < _busiest(n, best, threads):
            best = size
    return best
