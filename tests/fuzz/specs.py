"""Values a fuzz case describes but the parent cannot build: results of the module
(a Segmentation, a Feature, a sphere map), progress callbacks, non-contiguous
views and mutations of arrays computed in the child. They pickle as plain
descriptions and are resolved in the worker (resolve()), so a case file holds
only numpy arrays, Python scalars and these specs.

Array mutations are functions of (array, u) with u in [0, 1) standing for a
position ("the element at u * len"), so the parent can choose a mutation for an
array whose length only the child knows.
"""
import numpy as np


class Call:
    """module.<target>(*args, **kwargs) computed in the child before the call under
    test; then .attr read, or .method() called, on the result when given."""

    def __init__(self, target, args=(), kwargs=None, attr=None, method=None):
        self.target, self.args, self.kwargs = target, tuple(args), dict(kwargs or {})
        self.attr, self.method = attr, method

    def __repr__(self):
        tail = f".{self.attr}" if self.attr else (f".{self.method}()" if self.method else "")
        return f"<{self.target}(...){tail}>"


class Apply:
    """MUTATIONS[name](value, *params) applied in the child to a resolved value."""

    def __init__(self, name, value, *params):
        self.name, self.value, self.params = name, value, params

    def __repr__(self):
        return f"<{self.name}({self.value!r}, {', '.join(map(repr, self.params))})>"


class Callback:
    """A progress callback of one kind: 'true', 'none', 'false', 'after' (False after
    `count` calls), 'raise' (raises FuzzCallbackError), 'no_truth' (returns an array
    of two elements), 'bad_bool' (returns an object whose __bool__ raises),
    'nan' (returns float nan), 'string' (returns 'stop'), 'wrong_arity'
    (takes no arguments)."""

    def __init__(self, kind, count=0):
        self.kind, self.count = kind, count

    def __repr__(self):
        return f"<progress {self.kind}{'(%d)' % self.count if self.kind == 'after' else ''}>"


class FuzzCallbackError(Exception):
    """Raised by a 'raise' progress callback: the call must give it back unchanged."""


class _BadBool:
    def __bool__(self):
        raise FuzzCallbackError("__bool__ of the callback's return value")


def make_callback(spec):
    kind = spec.kind
    calls = [0]

    if kind == "wrong_arity":
        return lambda: True

    def callback(fraction, stage):
        calls[0] += 1
        if kind == "true":
            return True
        if kind == "none":
            return None
        if kind == "false":
            return False
        if kind == "after":
            return calls[0] <= spec.count
        if kind == "raise":
            raise FuzzCallbackError(f"progress callback raised at {fraction!r} ({stage!r})")
        if kind == "no_truth":
            return np.array([True, False])
        if kind == "bad_bool":
            return _BadBool()
        if kind == "nan":
            return float("nan")
        if kind == "string":
            return "stop"
        raise ValueError(f"unknown callback kind {kind!r}")

    return callback


# --- array mutations (parent or child side) --------------------------------------

def _at(a, u):
    return min(int(u * len(a)), len(a) - 1) if len(a) else 0


def _float_copy(a):
    a = np.array(a, dtype=np.float64, copy=True)
    return a


def _set_value(value):
    def mutate(a, u):
        a = _float_copy(a)
        if a.size:
            a.reshape(len(a), -1)[_at(a, u)] = value
        return a
    return mutate


def _scale(factor):
    def mutate(a, u):
        return _float_copy(a) * factor
    return mutate


def _strided(a, u=0.0):
    a = np.asarray(a)
    big = np.zeros((2 * len(a),) + a.shape[1:], dtype=a.dtype)
    big[::2] = a
    return big[::2]


def _fortran(a, u=0.0):
    return np.asfortranarray(np.asarray(a))


def _drop_row(a, u):
    a = np.asarray(a)
    return np.delete(a, _at(a, u), axis=0) if len(a) else a


def _add_row(a, u):
    a = np.asarray(a)
    return np.concatenate([a, a[_at(a, u):_at(a, u) + 1]]) if len(a) else a


def _empty(a, u=0.0):
    a = np.asarray(a)
    return a[:0]


def _transpose(a, u=0.0):
    return np.ascontiguousarray(np.asarray(a).T)


def _flatten(a, u=0.0):
    return np.asarray(a).ravel()


def _add_axis(a, u=0.0):
    return np.asarray(a)[..., None]


def _as_dtype(dtype):
    def mutate(a, u=0.0):
        a = np.asarray(a)
        if dtype is str:
            return a.astype(str)
        return a.astype(dtype)
    return mutate


def _as_list(a, u=0.0):
    return np.asarray(a).tolist()


def _zeros(a, u=0.0):
    return np.zeros_like(np.asarray(a))


def _index_value(value):
    def mutate(a, u):
        a = np.array(a, copy=True)
        if a.size:
            a = a.astype(np.int64)
            a.reshape(-1)[min(int(u * a.size), a.size - 1)] = value
        return a
    return mutate


def _shuffle(a, u):
    a = np.array(a, copy=True)
    rng = np.random.default_rng(int(u * 2 ** 31))
    rng.shuffle(a)
    return a


def _columns_first(a, u=0.0):
    """Swaps columns 0 and 1 (a face turned over, a coordinate swap)."""
    a = np.array(a, copy=True)
    if a.ndim == 2 and a.shape[1] >= 2:
        a[:, [0, 1]] = a[:, [1, 0]]
    return a


MUTATIONS = {
    "nan": _set_value(np.nan),
    "inf": _set_value(np.inf),
    "neg_inf": _set_value(-np.inf),
    "huge": _set_value(1e200),
    "tiny": _set_value(1e-200),
    "denormal": _set_value(5e-324),
    "scale_1e200": _scale(1e200),
    "scale_1e-200": _scale(1e-200),
    "scale_1e150": _scale(1e150),
    "scale_1e-150": _scale(1e-150),
    "scale_neg": _scale(-1.0),
    "zeros": _zeros,
    "strided": _strided,
    "fortran": _fortran,
    "drop_row": _drop_row,
    "add_row": _add_row,
    "empty": _empty,
    "transpose": _transpose,
    "flatten": _flatten,
    "add_axis": _add_axis,
    "float32": _as_dtype(np.float32),
    "float16": _as_dtype(np.float16),
    "int32": _as_dtype(np.int32),
    "int64": _as_dtype(np.int64),
    "uint32": _as_dtype(np.uint32),
    "int16": _as_dtype(np.int16),
    "int8": _as_dtype(np.int8),
    "float64": _as_dtype(np.float64),
    "bool": _as_dtype(np.bool_),
    "complex": _as_dtype(np.complex128),
    "object": _as_dtype(object),
    "str": _as_dtype(str),
    "list": _as_list,
    "shuffle": _shuffle,
    "swap_columns": _columns_first,
    "index_minus1": _index_value(-1),
    "index_huge": _index_value(2 ** 31 - 1),
    "index_2e40": _index_value(2 ** 40),
    "index_big": _index_value(10 ** 6),
    "index_min": _index_value(-2 ** 31),
}


def _dict_mutation(d, key_u, op, u):
    """A Feature.to_arrays() dict with one entry changed: key chosen by key_u, op one of
    MUTATIONS or 'delete', 'none', 'scalar', 'string'."""
    d = dict(d)
    keys = sorted(d)
    if not keys:
        return d
    key = keys[min(int(key_u * len(keys)), len(keys) - 1)]
    if op == "delete":
        del d[key]
    elif op == "none":
        d[key] = None
    elif op == "scalar":
        d[key] = 3
    elif op == "string":
        d[key] = "x"
    elif op == "extra":
        d["unknown_key"] = np.zeros(3)
    else:
        value = d[key]
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value[()]
        if isinstance(value, np.ndarray) or isinstance(value, (list, tuple)):
            d[key] = MUTATIONS[op](np.asarray(value), u)
        elif isinstance(value, (int, float, np.number)):
            d[key] = {"nan": float("nan"), "inf": float("inf"), "zeros": 0}.get(op, -1)
    return d


def _stack_spheres(a, b, u=0.0):
    return np.concatenate([np.asarray(a), np.asarray(b)])


def _normalise_rows(a, u=0.0):
    a = np.asarray(a, dtype=np.float64)
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def _rows(a, indices):
    return np.asarray(a)[np.asarray(indices, dtype=np.int64)]


def _corner_values(faces, columns, u=0.0):
    rows = 3 * len(np.asarray(faces))
    return np.random.default_rng(int(u * 2 ** 31)).standard_normal((rows, columns))


def _rbf_values(rbf_centres, columns, u=0.0):
    return np.random.default_rng(int(u * 2 ** 31)).standard_normal((len(rbf_centres), columns))


CHILD_FUNCTIONS = {
    "dict": _dict_mutation,
    "stack": _stack_spheres,
    "normalise": _normalise_rows,
    "rows": _rows,
    "corner_values": _corner_values,
    "rbf_values": _rbf_values,
}


def resolve(value, module):
    """Builds the value a spec stands for, inside the worker."""
    if isinstance(value, Call):
        fn = lookup(module, value.target)
        out = fn(*[resolve(a, module) for a in value.args],
                 **{k: resolve(v, module) for k, v in value.kwargs.items()})
        if value.attr:
            out = getattr(out, value.attr)
        if value.method:
            out = getattr(out, value.method)()
        return out
    if isinstance(value, Apply):
        fn = CHILD_FUNCTIONS.get(value.name) or MUTATIONS[value.name]
        return fn(resolve(value.value, module), *[resolve(p, module) for p in value.params])
    if isinstance(value, Callback):
        return make_callback(value)
    if isinstance(value, tuple):
        return tuple(resolve(v, module) for v in value)
    if isinstance(value, list):
        return [resolve(v, module) for v in value]
    if isinstance(value, dict):
        return {k: resolve(v, module) for k, v in value.items()}
    return value


def lookup(module, target):
    """'sphere_map' -> module.sphere_map; 'PasteSession.update' -> module.PasteSession.update
    (an instance method, called with the receiver first)."""
    obj = module
    for part in target.split("."):
        obj = getattr(obj, part)
    return obj


def has_callback(value, kind):
    if isinstance(value, Callback):
        return value.kind == kind
    if isinstance(value, Call):
        return has_callback(value.args, kind) or has_callback(value.kwargs, kind)
    if isinstance(value, Apply):
        return has_callback(value.value, kind) or has_callback(value.params, kind)
    if isinstance(value, (list, tuple)):
        return any(has_callback(v, kind) for v in value)
    if isinstance(value, dict):
        return any(has_callback(v, kind) for v in value.values())
    return False


def describe(value, depth=0):
    """A short, readable description of an argument for summaries."""
    if isinstance(value, np.ndarray):
        flags = "" if value.flags.c_contiguous or value.ndim == 0 else (
            " F" if value.flags.f_contiguous else " strided")
        extra = ""
        if value.dtype.kind == "f" and value.size:
            bad = ~np.isfinite(value)
            if bad.any():
                extra = f" {int(bad.sum())} non-finite"
            else:
                m = np.abs(value).max()
                if m > 1e100 or (0 < m < 1e-100):
                    extra = f" max|x|={m:.1e}"
        elif value.dtype.kind in "iu" and value.size:
            extra = f" [{value.min()}..{value.max()}]"
        return f"array{tuple(value.shape)} {value.dtype}{flags}{extra}"
    if isinstance(value, (Call, Apply, Callback)):
        return repr(value)
    if isinstance(value, (list, tuple)):
        if depth > 0 or len(value) > 6:
            return f"{type(value).__name__}[{len(value)}]"
        return "(" + ", ".join(describe(v, depth + 1) for v in value) + ")"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {describe(v, depth + 1)}" for k, v in value.items()) + "}"
    if isinstance(value, str) and len(value) > 20:
        return repr(value[:16] + "...") + f"[{len(value)}]"
    return repr(value)
