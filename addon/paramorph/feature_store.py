"""Copied features kept in the .blend (thesis ch. 5): each one is a Mesh
datablock named "Feature <source object>" with a fake user (so it is saved
with the file, survives File > Clean Up and can be appended from another
file), holding the feature's own faces for display and, as ID properties,
every array of `Feature.to_arrays()` (flat, with its shape and dtype kind).
The last copied one (highest serial) is the one Paste Feature uses unless
it names another. numpy in and out; no Python loops over elements."""
import bpy
import numpy as np

KEY = "paramorph_feature"          # group of flat arrays
SHAPES = "paramorph_feature_shapes"  # group: name -> shape
KINDS = "paramorph_feature_kinds"    # group: name -> "f" or "i"
SOURCE = "paramorph_feature_source"  # source object's name
FACES = "paramorph_feature_faces"    # number of source triangles selected
SERIAL = "paramorph_feature_serial"  # copy order: the highest is the last copied
VERSION = "paramorph_feature_version"
FORMAT_VERSION = 1


def is_feature(datablock):
    return datablock.get(VERSION) is not None and datablock.get(KEY) is not None


def features():
    """The stored features, oldest first."""
    return sorted((m for m in bpy.data.meshes if is_feature(m)), key=lambda m: int(m[SERIAL]))


def latest():
    stored = features()
    return stored[-1] if stored else None


def find(name=""):
    """The feature datablock called `name`, or the last copied one for ""; None if none."""
    if not name:
        return latest()
    mesh = bpy.data.meshes.get(name)
    return mesh if mesh is not None and is_feature(mesh) else None


def _same_selection(datablock, source_name, arrays):
    if datablock.get(SOURCE) != source_name:
        return False
    stored = np.asarray(datablock[KEY]["source_faces"])
    return np.array_equal(stored, np.asarray(arrays["source_faces"]).ravel())


def store(arrays, source_name, polygons=None):
    """Stores the arrays of Feature.to_arrays() copied from `source_name`;
    returns the datablock (`polygons`: how many faces were selected, shown
    in the panel; default the feature's triangles). A feature of the same faces of the same object is
    overwritten (a redo of Copy Feature), any other is kept beside it."""
    datablock = next((m for m in features() if _same_selection(m, source_name, arrays)), None)
    if datablock is None:
        datablock = bpy.data.meshes.new(f"Feature {source_name}")
    datablock.use_fake_user = True
    _fill_geometry(datablock, np.asarray(arrays["vertices"]), np.asarray(arrays["faces"]))
    flat, shapes, kinds = {}, {}, {}
    for name, value in arrays.items():
        value = np.asarray(value)
        kind = "f" if value.dtype.kind == "f" else "i"
        # ID properties hold 1-D double or int32 arrays (not uint8, not 0-d).
        flat[name] = np.ascontiguousarray(value.ravel(), dtype=np.float64 if kind == "f" else np.int32)
        shapes[name] = list(value.shape) if value.ndim else [-1]   # -1: a scalar
        kinds[name] = kind
    datablock[KEY] = flat
    datablock[SHAPES] = {name: np.asarray(shape, dtype=np.int32) for name, shape in shapes.items()}
    datablock[KINDS] = kinds
    datablock[SOURCE] = source_name
    datablock[FACES] = int(np.asarray(arrays["faces"]).shape[0] if polygons is None else polygons)
    datablock[SERIAL] = 1 + max((int(m[SERIAL]) for m in features() if m != datablock), default=0)
    datablock[VERSION] = FORMAT_VERSION
    return datablock


def load_arrays(datablock):
    """The dict Feature.from_arrays() takes, from a stored datablock."""
    flat, shapes, kinds = datablock[KEY], datablock[SHAPES], datablock[KINDS]
    arrays = {}
    for name in flat.keys():
        kind = kinds[name]
        value = np.array(flat[name], dtype=np.float64 if kind == "f" else np.int32)
        shape = [int(s) for s in shapes[name]]
        if shape == [-1]:
            value = value.reshape(())  # a scalar (0-d array)
        else:
            value = value.reshape(shape)
        if name == "mask":
            value = value.astype(np.uint8)
        arrays[name] = value
    return arrays


def describe(datablock):
    return f"{datablock.name} (from {datablock.get(SOURCE, '?')}, {datablock.get(FACES, 0)} faces)"


def _fill_geometry(mesh, V, F):
    """The feature's own faces (in its frame), so the datablock shows what it holds."""
    mesh.clear_geometry()
    V = np.ascontiguousarray(V, dtype=np.float32).reshape(-1, 3)
    F = np.ascontiguousarray(F, dtype=np.int32).reshape(-1, 3)
    mesh.vertices.add(len(V))
    mesh.vertices.foreach_set("co", V.ravel())
    mesh.loops.add(3 * len(F))
    mesh.loops.foreach_set("vertex_index", F.ravel())
    mesh.polygons.add(len(F))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(F), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(F), 3, dtype=np.int32))
    mesh.update(calc_edges=True)
