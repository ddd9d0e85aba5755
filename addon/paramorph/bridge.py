"""Blender <-> numpy bridge: mesh arrays out, UV layers and shape keys in.
foreach_get/foreach_set with matching dtypes; no Python loops over elements."""
import contextlib

import bpy
import numpy as np

from .native import load_error, native


def require_native():
    if native is None:
        raise RuntimeError(load_error)
    return native


def mesh_arrays(mesh, polygons=False, loops=False):
    """V float64 (n,3), F int32 (m,3) loop triangles, and on request tri_poly
    int32 (m,) (each triangle's polygon) and tri_loops int32 (m,3) (None
    otherwise: each costs a pass over the triangles)."""
    n = len(mesh.vertices)
    co = np.empty(3 * n, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)  # float32: a copy; float64 would convert per element
    mesh.calc_loop_triangles()
    m = len(mesh.loop_triangles)
    F = np.empty(3 * m, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", F)
    tri_poly = tri_loops = None
    if polygons:
        tri_poly = np.empty(m, dtype=np.int32)
        mesh.loop_triangles.foreach_get("polygon_index", tri_poly)
    if loops:
        tri_loops = np.empty(3 * m, dtype=np.int32)
        mesh.loop_triangles.foreach_get("loops", tri_loops)
        tri_loops = tri_loops.reshape(m, 3)
    return co.reshape(n, 3).astype(np.float64), F.reshape(m, 3), tri_poly, tri_loops


def as_placed(V, obj):
    """Vertices turned and scaled by the object's transform, about its origin:
    what the operators compute on, so a mesh scaled unevenly in Object Mode is
    mapped as it looks (issue 20). Results go back in the object's own
    coordinates."""
    return V @ np.array(obj.matrix_world, dtype=np.float64)[:3, :3].T


def evaluated_arrays(context, obj):
    """V, F (loop triangles) of the object as the viewport shows it: its
    visible modifiers applied (a Subdivision Surface's smooth shape). For
    operators that only read a mesh; those writing per vertex use the base
    mesh and say so (modifier_note)."""
    evaluated = obj.evaluated_get(context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        V, F, _, _ = mesh_arrays(mesh)
    finally:
        evaluated.to_mesh_clear()
    return V, F


def modifier_note(obj):
    """'' or a sentence saying the computation used the mesh without its
    (visible) modifiers, naming them."""
    names = [m.name for m in obj.modifiers if m.show_viewport]
    if not names:
        return ""
    return (f"{obj.name}: computed on the mesh without its modifiers ({', '.join(names)}); "
            "apply them first to include them")


def sphere_uv(mesh, positions):
    """Per-loop (u, v) from spherical coordinates, with the seam handled: a
    polygon whose u values span more than half the texture gets its small u
    shifted by +1, and loops at a pole take their polygon's mean u."""
    num_loops = len(mesh.loops)
    loop_vertex = np.empty(num_loops, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    P = len(mesh.polygons)
    loop_start = np.empty(P, dtype=np.int32)
    loop_total = np.empty(P, dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", loop_start)
    mesh.polygons.foreach_get("loop_total", loop_total)
    poly_of_loop = np.empty(num_loops, dtype=np.int64)
    poly_of_loop[np.repeat(loop_start, loop_total) + _ranks(loop_total)] = np.repeat(
        np.arange(P), loop_total)

    X = positions[loop_vertex]
    u = 0.5 + np.arctan2(X[:, 1], X[:, 0]) / (2.0 * np.pi)
    v = 0.5 + np.arcsin(np.clip(X[:, 2], -1.0, 1.0)) / np.pi
    pole = np.abs(X[:, 2]) > 1.0 - 1e-9

    # Per-polygon reductions over each polygon's contiguous loops (reduceat
    # wants ascending starts: visit polygons in loop order).
    order = np.argsort(loop_start, kind="stable")
    starts = loop_start[order]

    def per_poly(values, reduce):
        out = np.empty(P, dtype=values.dtype)
        out[order] = reduce.reduceat(values, starts)
        return out

    free = ~pole
    umax = per_poly(np.where(free, u, -np.inf), np.maximum)
    umin = per_poly(np.where(free, u, np.inf), np.minimum)
    wraps = (umax - umin) > 0.5
    u = np.where(wraps[poly_of_loop] & (u < 0.5), u + 1.0, u)
    if pole.any():
        total = per_poly(np.where(free, u, 0.0), np.add)
        count = per_poly(free.astype(np.float64), np.add)
        mean = np.divide(total, count, out=np.full(P, 0.5), where=count > 0)
        u = np.where(pole, mean[poly_of_loop], u)
    return np.stack([u, v], axis=1)


def _ranks(loop_total):
    """0, 1, ..., t-1 for each polygon, concatenated."""
    starts = np.repeat(np.cumsum(loop_total) - loop_total, loop_total)
    return np.arange(int(loop_total.sum())) - starts


def write_uv_layer(mesh, uv, name):
    """Creates (or overwrites) the UV layer `name` from per-loop (u, v)."""
    layer = mesh.uv_layers.get(name) or mesh.uv_layers.new(name=name)
    flat = np.ascontiguousarray(uv, dtype=np.float32).ravel()
    if hasattr(layer, "uv"):  # 3.5+
        layer.uv.foreach_set("vector", flat)
    else:
        layer.data.foreach_set("uv", flat)
    mesh.update()
    return layer


def add_shape_key(obj, coordinates, name, value=0.0):
    """Adds (or overwrites) shape key `name` with (n,3) coordinates; a Basis
    key is created first when the object has none."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    key = obj.data.shape_keys.key_blocks.get(name) or obj.shape_key_add(name=name, from_mix=False)
    key.data.foreach_set("co", np.ascontiguousarray(coordinates, dtype=np.float32).ravel())
    key.value = value
    obj.data.update()
    return key


@contextlib.contextmanager
def object_mode(context, obj, face_select=False):
    """Object-mode mesh data for the duration (foreach_set writes go to the
    mesh, not to the Edit Mode copy), then back to the mode it was in. With
    face_select, Edit Mode comes back in face select mode, so a face
    selection written here is not widened to faces whose vertices are all
    selected."""
    mode = obj.mode
    if mode != "OBJECT":
        with context.temp_override(active_object=obj, object=obj):
            bpy.ops.object.mode_set(mode="OBJECT")
    try:
        yield obj
    finally:
        if mode == "EDIT" and face_select:
            context.tool_settings.mesh_select_mode = (False, False, True)
        if mode != "OBJECT":
            with context.temp_override(active_object=obj, object=obj):
                bpy.ops.object.mode_set(mode=mode)


def write_sphere_map(obj, V, positions, uv_name="Sphere", key_name="Sphere", shape_key=True, mapped=None):
    """UV layer `uv_name` from the map's (n, 3) `positions` and, optionally,
    shape key `key_name` (the sphere scaled to the mesh's bounding sphere).
    mapped: mask of the vertices the map covers (None: all); the others (parts
    a repair left out) keep their place in the shape key and take their
    direction from the centre in the UVs."""
    mesh = obj.data
    center = 0.5 * (V.min(axis=0) + V.max(axis=0))
    positions = np.asarray(positions, dtype=np.float64)
    if mapped is not None and not mapped.all():
        direction = V[~mapped] - center
        positions = positions.copy()
        positions[~mapped] = direction / np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-300)
    write_uv_layer(mesh, sphere_uv(mesh, positions), uv_name)
    if shape_key:
        radius = float(np.linalg.norm(V - center, axis=1).max())
        key = center + radius * positions
        if mapped is not None:
            key[~mapped] = V[~mapped]
        add_shape_key(obj, key, key_name)


def sphere_map_object(obj, uv_name="Sphere", key_name="Sphere", **options):
    """Sphere-maps a mesh object: UV layer `uv_name` and shape key `key_name`
    (the sphere scaled to the mesh's bounding sphere). The native call runs
    first, so a failure leaves the object untouched. Returns the native result."""
    pm = require_native()
    V, F, _, _ = mesh_arrays(obj.data)
    result = pm.sphere_map(V, F, **options)
    write_sphere_map(obj, V, result.positions, uv_name, key_name)
    return result
