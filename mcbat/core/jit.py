"""The one place for numba options used by every jitted function in mcbat.

``cache=True``
    compiled machine code is stored next to the sources, so warm starts skip LLVM.
    numba checks only the timestamp of the file that defines a cached function, not of the
    modules it calls: after editing ``mcbat/core`` in a checkout, delete the caches
    (``find mcbat -name __pycache__ -exec rm -rf {} +``). Installed releases are not
    affected (an upgrade rewrites every file).
``fastmath=False``
    strict IEEE arithmetic. Besides the NaN checks the status codes rely on, it makes the
    results bitwise identical wherever a kernel is compiled: inlined into the parallel
    batch loop or called alone by the single-impact API, on any thread count, and on any
    x86-64 CPU with the same library versions (FMA contraction alone was 5 % faster but
    changed last bits between those contexts, which the adaptive step can amplify to
    1e-9).
``error_model="numpy"``
    division by zero gives inf/NaN instead of raising, so kernels never raise inside
    ``prange``; the solvers check their inputs and report a status code instead.
``nogil=True``
    kernels can run in threads (the Dask engine, thread pools) concurrently.
"""

import threading

import numba
import numba.experimental.function_type  # noqa: F401 - registers FunctionAddress's type
from numba.core.types import WrapperAddressProtocol

__all__ = ["JIT_OPTIONS", "FunctionAddress", "await_group", "compiled_elsewhere", "is_cold",
           "njit", "said_compiling"]

JIT_OPTIONS = {"cache": True, "fastmath": False, "error_model": "numpy", "nogil": True}


def njit(*args, **overrides):
    """``numba.njit`` with the project's options (``overrides`` win)."""
    options = {**JIT_OPTIONS, **overrides}
    if args and callable(args[0]):
        return numba.njit(**options)(args[0])
    return numba.njit(*args, **options)


def is_cold(dispatcher):
    """True when calling ``dispatcher`` (a numba function) will compile it first: no
    machine code in this process, and none in its on-disk cache for this CPU and source;
    False when it will not; None when this numba's cache cannot be read this way.

    The test reads the cache's index as numba's own lookup does (by the CPU and the
    function's bytecode; the argument types are not compared), without compiling or
    loading anything.
    """
    if dispatcher.signatures:
        return False  # compiled (or loaded from the cache) in this process already
    try:
        cache = dispatcher._cache  # numba's internals: any change means "unknown"
        index = cache._cache_file._load_index()  # {} without a file, or for an old source
        wanted = cache._index_key(None, dispatcher.targetctx.codegen())[1:]
    except Exception:  # noqa: BLE001 - an unknown state, never a failed run
        return None
    return not any(tuple(key[1:]) == wanted for key in index)


# Kernel groups (``mcbat.cli.compiling.KERNEL_GROUPS``) that another process is compiling
# into the on-disk cache for this one (``mcbat.cli.precompile``), and how to wait for it.
_elsewhere: dict = {"groups": frozenset(), "wait": None}
_elsewhere_lock = threading.Lock()


def compiled_elsewhere(groups, wait) -> None:
    """Record that another process is compiling the kernel ``groups`` (names) into the
    cache; ``wait()`` returns once it is done (or gone). ``await_group`` calls it before
    this process's first call of one of those groups, so that the call loads the machine
    code instead of compiling it a second time. ``compiled_elsewhere((), None)`` forgets."""
    with _elsewhere_lock:
        _elsewhere["groups"], _elsewhere["wait"] = frozenset(groups), wait


def await_group(group: str) -> None:
    """Before calling a kernel of ``group``: if another process is compiling that group
    for this one, wait for it (once; a no-op otherwise)."""
    if group not in _elsewhere["groups"]:
        return
    with _elsewhere_lock:
        wait = _elsewhere["wait"] if group in _elsewhere["groups"] else None
        _elsewhere["groups"], _elsewhere["wait"] = frozenset(), None
    if wait is not None:
        wait()


class FunctionAddress(WrapperAddressProtocol):
    """A jitted function handed to a kernel as an argument, called by its address.

    A kernel that calls a jitted function directly carries the callee's whole call tree
    in its own compile: typing it, and generating its machine code again. Handed over as
    a ``FunctionAddress``, the callee is typed by ``signature`` alone, so the kernel
    compiles without it (meanwhile another process may compile the callee: ``group``),
    and the callee is compiled, or loaded from the cache, once, when the kernel is first
    called. Used where the call costs little beside the callee's own work: an impact per
    call.

    Parameters
    ----------
    dispatcher : numba dispatcher
        The function (``mcbat.core.jit.njit``).
    signature : numba signature
        Its one signature: argument types exactly as the callers pass them.
    group : str, optional
        The kernel group the function belongs to: before compiling it, wait for another
        process compiling that group (``await_group``).
    """

    def __init__(self, dispatcher, signature, group=None):
        self.dispatcher, self._signature, self.group = dispatcher, signature, group

    def signature(self):
        """The function's numba signature (the kernel's argument type)."""
        return self._signature

    def __wrapper_address__(self):
        """The address of the function's C wrapper (numba calls it at each kernel call,
        with the arguments unboxed; the first one compiles or loads the function)."""
        args = tuple(self._signature.args)
        if args not in self.dispatcher.overloads:
            if self.group is not None:
                await_group(self.group)
            # (by its argument types, as a call compiles it: the cache's key; the whole
            # signature would be a key of its own)
            self.dispatcher.compile(args)
        result = self.dispatcher.overloads[args]
        return result.library.get_pointer_to_function(result.fndesc.llvm_cfunc_wrapper_name)


#: The line this command printed to say that it compiles (``mcbat.cli.compiling``,
#: ``mcbat.runner.compiling``), None before: each says it once, whichever comes first.
said_compiling: dict = {"line": None}
