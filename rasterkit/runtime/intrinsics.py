"""LLVM operations that Numba does not expose: a software prefetch, an atomic add and an
atomic read, a spin-wait hint, 8-byte loads and stores at any byte offset, the bits of a
float64 as an int64 and back, a kernel's scratch floats on its stack, and a float kept
as it is (:func:`kept`).

Prefetch
--------
The triangle bands visit their records through an index list (``items``): each record
sits at an unpredictable place in three record arrays, and the hardware prefetchers cannot
guess it, so every triangle began with up to three cache misses (about 15 % of the band
pass on the bunny). :func:`prefetch_row` asks for a row a few iterations ahead, so it is in
the cache when the loop gets there.

A prefetch never faults, even for an address outside the array, and changes no result:
it only moves memory into the cache earlier.

Atomic add
----------
A fixed share of the work per thread leaves one thread idle at the end when the shares
cost different amounts (bands of an image differ) or the machine takes a core away for a
while. With :func:`fetch_add` on a shared counter each thread takes the unclaimed piece of work as it becomes free (the workers of
:func:`rasterkit.runtime.threads.run_parallel`: ``while True: piece = fetch_add(counter, 0, 1)``, until
``piece`` passes the number of pieces). A Numba generator would say it shorter, but a cached
kernel that uses a generator compiled in another process fails to compile (Numba 0.68).
Which thread draws a band never changes what is drawn into it, so images stay
bit-identical.
"""

from __future__ import annotations

import platform

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["bits_float", "fetch_add", "float_bits", "kept", "load_acquire", "load_word", "pause", "prefetch_row",
           "prefetch_texel", "stack_floats", "store_word"]


@intrinsic
def prefetch_row(typingctx, array, row):
    """Prefetch the first cache line of ``array[row]`` (1-D: of the element ``array[row]``)
    for reading, into every cache level (LLVM's ``llvm.prefetch``, locality 3).

    ``array`` is a C-contiguous NumPy array; ``row`` an integer (not checked: a prefetch
    outside the array is harmless)."""
    if not isinstance(array, types.Array) or array.layout != "C" or not isinstance(row, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        array_type = signature.args[0]
        data = context.make_array(array_type)(context, builder, args[0])
        index = context.cast(builder, args[1], signature.args[1], types.intp)
        if array_type.ndim > 1:
            stride = cgutils.unpack_tuple(builder, data.strides)[0]
        else:
            stride = context.get_constant(types.intp, context.get_abi_sizeof(context.get_data_type(array_type.dtype)))
        _prefetch(builder, data.data, builder.mul(index, stride))
        return context.get_dummy_value()

    return types.void(array, row), codegen


def _prefetch(builder, data, offset):
    """Emit ``llvm.prefetch`` of the byte ``offset`` from the pointer ``data``: for reading
    (0), high temporal locality (3), the data cache (1)."""
    byte_pointer = ir.IntType(8).as_pointer()
    address = builder.gep(builder.bitcast(data, byte_pointer), [offset])
    i32 = ir.IntType(32)
    function_type = ir.FunctionType(ir.VoidType(), [byte_pointer, i32, i32, i32])
    function = cgutils.get_or_insert_function(builder.module, function_type, "llvm.prefetch.p0")
    builder.call(function, [address, ir.Constant(i32, 0), ir.Constant(i32, 3), ir.Constant(i32, 1)])


def _prefetch_element(array, indices):
    """The signature and code generator of a prefetch of ``array[indices]`` (C-contiguous,
    one integer index per dimension), or None for other types."""
    if not isinstance(array, types.Array) or array.layout != "C" or array.ndim != len(indices):
        return None
    if not all(isinstance(index, types.Integer) for index in indices):
        return None

    def codegen(context, builder, signature, args):
        array_type = signature.args[0]
        data = context.make_array(array_type)(context, builder, args[0])
        strides = cgutils.unpack_tuple(builder, data.strides)
        offset = context.get_constant(types.intp, 0)
        for value, kind, stride in zip(args[1:], signature.args[1:], strides):
            offset = builder.add(offset, builder.mul(context.cast(builder, value, kind, types.intp), stride))
        _prefetch(builder, data.data, offset)
        return context.get_dummy_value()

    return types.void(array, *indices), codegen


@intrinsic
def prefetch_texel(typingctx, array, m, j, i):
    """Prefetch the cache line of ``array[m, j, i]`` (a 3-D C-contiguous array) for reading,
    as :func:`prefetch_row` does (indices not checked: a prefetch outside the array is
    harmless)."""
    return _prefetch_element(array, (m, j, i))


@intrinsic
def prefetch_item(typingctx, array, row, column):
    """Prefetch the cache line of ``array[row, column]`` (a 2-D C-contiguous array) for
    reading, as :func:`prefetch_row` does (indices not checked: a prefetch outside the
    array is harmless)."""
    return _prefetch_element(array, (row, column))


@intrinsic
def fetch_add(typingctx, array, index, value):
    """Atomically add ``value`` to ``array[index]`` (a 1-D C-contiguous int64 array) and
    return the value it held before (sequentially consistent). ``index`` is not checked."""
    if not (isinstance(array, types.Array) and array.ndim == 1 and array.layout == "C"
            and array.dtype == types.int64 and isinstance(index, types.Integer)
            and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0])
        index = context.cast(builder, args[1], signature.args[1], types.intp)
        amount = context.cast(builder, args[2], signature.args[2], types.int64)
        address = builder.gep(data.data, [index])
        return builder.atomic_rmw("add", address, amount, "seq_cst")

    return types.int64(array, index, value), codegen



@intrinsic
def load_acquire(typingctx, array, index):
    """``array[index]`` (a 1-D C-contiguous int64 array) read atomically, with acquire
    ordering: a read that the compiler may not hoist out of a waiting loop and that sees the
    writes of another thread. ``index`` is not checked."""
    if not (isinstance(array, types.Array) and array.ndim == 1 and array.layout == "C"
            and array.dtype == types.int64 and isinstance(index, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0])
        index = context.cast(builder, args[1], signature.args[1], types.intp)
        return builder.load_atomic(builder.gep(data.data, [index]), "acquire", 8)

    return types.int64(array, index), codegen


_X86 = platform.machine().lower() in ("x86_64", "amd64", "i686", "i386")


@intrinsic
def pause(typingctx):
    """The processor's spin-wait hint (x86 ``pause``): a waiting loop gives the core's other
    hardware thread its resources and does not flood the memory system; nothing elsewhere."""

    def codegen(context, builder, signature, args):
        if _X86:
            function = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), []),
                                                      "llvm.x86.sse2.pause")
            builder.call(function, [])
        return context.get_dummy_value()

    return types.void(), codegen


def _byte_array(array) -> bool:
    return isinstance(array, types.Array) and array.ndim == 1 and array.layout == "C" and array.dtype == types.uint8


def _word_pointer(context, builder, signature, args):
    data = context.make_array(signature.args[0])(context, builder, args[0])
    offset = context.cast(builder, args[1], signature.args[1], types.intp)
    return builder.bitcast(builder.gep(data.data, [offset]), ir.IntType(64).as_pointer())


@intrinsic
def load_word(typingctx, array, offset):
    """The 8 bytes ``array[offset: offset + 8]`` of a 1-D C-contiguous uint8 array as one
    uint64 (native byte order, any alignment). ``offset`` is not checked. (What
    ``array.view(np.uint64)`` gives, without compiling NumPy's ``view`` in every kernel
    that uses it: about half a second each.)"""
    if not (_byte_array(array) and isinstance(offset, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        return builder.load(_word_pointer(context, builder, signature, args), align=1)

    return types.uint64(array, offset), codegen


@intrinsic
def store_word(typingctx, array, offset, value):
    """Write the uint64 ``value`` into the 8 bytes ``array[offset: offset + 8]`` of a 1-D
    C-contiguous uint8 array (native byte order, any alignment). ``offset`` is not checked."""
    if not (_byte_array(array) and isinstance(offset, types.Integer) and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, signature, args):
        word = context.cast(builder, args[2], signature.args[2], types.uint64)
        builder.store(word, _word_pointer(context, builder, signature, args), align=1)
        return context.get_dummy_value()

    return types.void(array, offset, value), codegen


@intrinsic
def float_bits(typingctx, x):
    """The IEEE 754 bits of the float64 ``x`` as an int64 (what ``x.view(np.int64)`` would
    be for a scalar)."""
    if x != types.float64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(x), codegen


@intrinsic
def bits_float(typingctx, i):
    """The float64 whose IEEE 754 bits are the int64 ``i`` (the inverse of :func:`float_bits`)."""
    if i != types.int64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(i), codegen


@intrinsic
def stack_floats(typingctx, n):
    """A 1-D float64 array of ``n`` (a literal int) elements on the calling kernel's stack,
    reserved once at its entry (not per loop iteration) and valid until it returns: scratch
    space for kernels compiled without reference counting, which cannot allocate (the array
    has no owner to count). Not initialised."""
    if not isinstance(n, types.IntegerLiteral):
        return None
    count = n.literal_value
    array_type = types.Array(types.float64, 1, "C")

    def codegen(context, builder, signature, args):
        block = cgutils.alloca_once(builder, ir.DoubleType(), size=count)
        array = context.make_array(array_type)(context, builder)
        intp = context.get_value_type(types.intp)
        context.populate_array(array, data=block, shape=[ir.Constant(intp, count)], strides=[ir.Constant(intp, 8)],
                               itemsize=ir.Constant(intp, 8), meminfo=None)
        return array._getvalue()

    return array_type(n), codegen


@intrinsic
def kept(typingctx, x):
    """The float ``x`` itself (``llvm.canonicalize``: the identity on every float but a
    signalling NaN, which it quiets; a multiplication by 1 on x86).

    For a store that keeps an element or replaces it, ``a[i] = z if win else kept(a[i])``:
    LLVM turns ``a[i] = z if win else a[i]`` in a vectorised loop into a masked store
    (``vmaskmovps``), which costs 3-4x a blend and a full store on AMD's cores (the depth
    test of a span measured 3.7x slower); it cannot see through this call, so it blends."""
    if not isinstance(x, types.Float):
        return None

    def codegen(context, builder, signature, args):
        kind = args[0].type
        function = builder.module.declare_intrinsic("llvm.canonicalize", [kind], ir.FunctionType(kind, [kind]))
        return builder.call(function, [args[0]])

    return x(x), codegen
