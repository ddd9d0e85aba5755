"""Writes a paste result (PasteSession.result()) into a Blender mesh, keeping
what was not touched as it was: polygons none of whose loop triangles were
replaced stay (quads stay quads) with all their data; polygons with a
replaced triangle are removed, their unreplaced triangles come back as
triangles and the new faces are added, each with the face data (material,
smooth shading, face attributes) of the polygon it came from; vertices keep
their data and take their new positions.

The topology change goes through one BMesh round trip (which carries every
layer: attributes, UVs, vertex groups, creases): the patch (new faces and
the kept triangles of cut polygons) is appended as a mesh and welded to the
old vertices, then the cut polygons are deleted. Temporary integer id
attributes say afterwards which final element is which, so positions and
face data are written with numpy, whatever order BMesh left them in."""
import contextlib

import bmesh
import bpy
import numpy as np

VERTEX_ID = "paramorph_paste_vertex_id"
FACE_ID = "paramorph_paste_face_id"


class PasteWriteError(Exception):
    """The result does not fit the mesh it was computed for."""


def plan(tri_poly, num_polygons, num_vertices, F, V2, F2, new_faces, replaced):
    """What changes, from the session's result (all numpy):
    cut: bool per polygon (a triangle of it was replaced);
    patch_faces (k, 3) in V2's numbering: the kept triangles of cut polygons,
    then the new faces;
    patch_tri (k,) the triangle of F each came from (new faces: -1, filled
    from the session's new_face_parents)."""
    m = len(tri_poly)
    replaced = np.asarray(replaced, dtype=np.int64)
    new_faces = np.asarray(new_faces, dtype=np.int64)
    is_replaced = np.zeros(m, dtype=bool)
    is_replaced[replaced] = True
    kept = np.flatnonzero(~is_replaced)
    if len(F2) < len(kept) or not np.array_equal(F2[:len(kept)], F[kept]):
        raise PasteWriteError("the paste result's untouched faces do not match the mesh")
    if len(V2) < num_vertices:
        raise PasteWriteError("the paste result has fewer vertices than the mesh")
    cut = np.zeros(num_polygons, dtype=bool)
    cut[tri_poly[replaced]] = True
    partial = np.flatnonzero(cut[tri_poly[kept]])     # rows of F2 (kept triangles of cut polygons)
    patch_faces = np.vstack([F2[partial], F2[new_faces]]).astype(np.int64)
    patch_tri = np.concatenate([kept[partial], np.full(len(new_faces), -1)]).astype(np.int64)
    return cut, patch_faces, patch_tri


def barycentric(points, A, B, C):
    """(k, 3) weights of `points` projected onto triangles (A, B, C), clamped
    to the triangle (non-negative, summing to 1)."""
    v0, v1, v2 = B - A, C - A, points - A
    d00, d01, d11 = (v0 * v0).sum(-1), (v0 * v1).sum(-1), (v1 * v1).sum(-1)
    d20, d21 = (v2 * v0).sum(-1), (v2 * v1).sum(-1)
    denom = d00 * d11 - d01 * d01
    denom = np.where(np.abs(denom) > 1e-300, denom, 1.0)
    b1 = (d11 * d20 - d01 * d21) / denom
    b2 = (d00 * d21 - d01 * d20) / denom
    w = np.clip(np.stack([1.0 - b1 - b2, b1, b2], axis=-1), 0.0, None)
    total = w.sum(axis=-1, keepdims=True)
    return np.where(total > 0, w / np.where(total > 0, total, 1.0), 1.0 / 3.0)


def _patch_mesh(V2, patch_faces, num_vertices):
    """A mesh of the patch: the old vertices it uses (to weld), then every new
    vertex in V2's order. Returns it and the old vertices it uses."""
    used_old = np.unique(patch_faces[patch_faces < num_vertices])
    new_ids = np.arange(num_vertices, len(V2))
    ids = np.concatenate([used_old, new_ids])
    local = np.empty(len(V2), dtype=np.int64)
    local[used_old] = np.arange(len(used_old))
    local[new_ids] = len(used_old) + np.arange(len(new_ids))
    faces = local[patch_faces]
    mesh = bpy.data.meshes.new("paramorph paste patch")
    mesh.vertices.add(len(ids))
    mesh.vertices.foreach_set("co", V2[ids].astype(np.float32).ravel())
    mesh.loops.add(3 * len(faces))
    mesh.loops.foreach_set("vertex_index", faces.astype(np.int32).ravel())
    mesh.polygons.add(len(faces))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(faces), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(faces), 3, dtype=np.int32))
    mesh.update(calc_edges=True)
    return mesh, used_old


def _set_ids(mesh, name, domain, values):
    attribute = mesh.attributes.get(name) or mesh.attributes.new(name=name, type="INT", domain=domain)
    attribute.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.int32))


def _get_ids(mesh, name):
    attribute = mesh.attributes[name]
    values = np.empty(len(attribute.data), dtype=np.int32)
    attribute.data.foreach_get("value", values)
    mesh.attributes.remove(attribute)
    return values.astype(np.int64)


# Attribute data type -> (field, numpy dtype, width) for foreach_get/set.
_FIELDS = {"FLOAT": ("value", np.float32, 1), "INT": ("value", np.int32, 1), "INT8": ("value", np.int32, 1),
           "BOOLEAN": ("value", bool, 1), "FLOAT_VECTOR": ("vector", np.float32, 3),
           "FLOAT2": ("vector", np.float32, 2), "FLOAT_COLOR": ("color", np.float32, 4),
           "BYTE_COLOR": ("color", np.float32, 4)}


def _attribute_layers(mesh, domain, skip, types):
    """(name, field, dtype, width) of the mesh's `domain` attributes of `types`,
    but not internal ones (".name") nor those named in `skip`."""
    layers = []
    for attribute in mesh.attributes:
        if attribute.domain != domain or attribute.name.startswith(".") or attribute.name in skip:
            continue
        if attribute.data_type in types:
            layers.append((attribute.name,) + _FIELDS[attribute.data_type])
    return layers


def _face_layers(mesh):
    """Face data to copy from source polygons: (collection, property, dtype, width)."""
    layers = [(("polygons",), "material_index", np.int32, 1), (("polygons",), "use_smooth", bool, 1)]
    return layers + _attribute_layers(mesh, "FACE", (FACE_ID, "material_index", "sharp_face"), _FIELDS)


def _corner_layers(mesh):
    """Corner data to interpolate on new faces: UV maps and corner attributes
    (not booleans: they do not interpolate)."""
    layers = [(("uv", uv.name), "uv", np.float32, 2) for uv in mesh.uv_layers]
    uv_names = {uv.name for uv in mesh.uv_layers}
    return layers + _attribute_layers(mesh, "CORNER", uv_names, set(_FIELDS) - {"BOOLEAN", "INT8"})


def _new_corners(mesh, polygons, vertex_ids, V, F, V2, triangles, tri_loops):
    """For the new (triangle) polygons: their loops (k, 3), the barycentric
    weights (k, 3, 3) of each corner in its source triangle, and the source
    triangle's loops (k, 3, 3) (old loop numbering) the weights apply to."""
    loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", loop_start)
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    loops = loop_start[polygons, None] + np.arange(3)
    points = V2[vertex_ids[loop_vertex[loops]]]                   # (k, 3, 3)
    corners3d = V[F[triangles]]                                   # (k, 3 sources, 3)
    A, B, C = (corners3d[:, None, i, :] for i in range(3))
    weights = barycentric(points, A, B, C)                        # (k, 3 corners, 3 sources)
    sources = np.broadcast_to(tri_loops[triangles][:, None, :], weights.shape)
    return loops, weights, sources


def _data(mesh, where):
    """The collection a layer lives in, looked up afresh (a BMesh round trip
    replaces the mesh's layers): an attribute name, ("uv", name) or ("polygons",)."""
    if isinstance(where, str):
        return mesh.attributes[where].data
    if where[0] == "uv":
        return mesh.uv_layers[where[1]].data
    return mesh.polygons


def _read(mesh, layer):
    collection, field, dtype, width = layer
    data = _data(mesh, collection)
    values = np.empty(len(data) * width, dtype=dtype)
    data.foreach_get(field, values)
    return values.reshape(len(data), width) if width > 1 else values


def _write(mesh, layer, values):
    collection, field, dtype, width = layer
    data = _data(mesh, collection)
    data.foreach_set(field, np.ascontiguousarray(values, dtype=dtype).ravel())


def write(mesh, V, F, tri_poly, V2, F2, new_faces, replaced, new_face_parents):
    """Writes the result into `mesh` (object-mode data); new_face_parents: per
    new face, the triangle of F it lies in (PasteSession.new_face_parents).
    Returns a dict: polygons kept, polygons removed, faces added, vertices added."""
    n, P = len(mesh.vertices), len(mesh.polygons)
    V2 = np.asarray(V2, dtype=np.float64)
    F2 = np.asarray(F2, dtype=np.int64)
    cut, patch_faces, patch_tri = plan(tri_poly, P, n, F, V2, F2, new_faces, replaced)
    if len(patch_faces) == 0 and len(V2) == n:  # the detail fits the mesh: vertices moved only
        mesh.vertices.foreach_set("co", V2.astype(np.float32).ravel())
        mesh.update()
        return {"kept": P, "removed": 0, "added": 0, "triangulated": 0, "new_vertices": 0,
                "new_polygons": np.empty(0, dtype=np.int64),
                "moved_vertices": np.flatnonzero(np.any(V2 != V, axis=1))}
    is_new = patch_tri < 0
    parents = np.asarray(new_face_parents, dtype=np.int64)
    if len(parents) != is_new.sum():
        raise PasteWriteError("the paste result names a parent for each new face: lengths differ")
    patch_tri[is_new] = parents
    patch_source = tri_poly[patch_tri]

    face_layers = _face_layers(mesh)
    old_face_data = [_read(mesh, layer) for layer in face_layers]
    corner_layers = _corner_layers(mesh)
    old_corner_data = [_read(mesh, layer) for layer in corner_layers]
    mesh.calc_loop_triangles()
    tri_loops = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", tri_loops)
    tri_loops = tri_loops.reshape(-1, 3)

    backup = mesh.copy()  # a failure half way puts everything back
    try:
        new_polygons = _rebuild(mesh, n, P, V, F, V2, cut, patch_faces, patch_tri, patch_source,
                                face_layers, old_face_data, corner_layers, old_corner_data, tri_loops)
    except BaseException:
        _restore(mesh, backup)
        raise
    finally:
        bpy.data.meshes.remove(backup)
    mesh.update()
    return {"kept": int(P - cut.sum()), "removed": int(cut.sum()), "added": int(is_new.sum()),
            "triangulated": int((~is_new).sum()), "new_vertices": int(len(V2) - n),
            "new_polygons": new_polygons}


@contextlib.contextmanager
def _uv_map_choices_kept(mesh):
    """The artist's active UV map and render UV map, as they were: from 5.0 a
    BMesh that also took in a mesh without UV maps (the patch) makes the first
    map both again on to_mesh."""
    active = mesh.uv_layers.active.name if mesh.uv_layers.active else None
    render = next((layer.name for layer in mesh.uv_layers if layer.active_render), None)
    try:
        yield
    finally:
        if mesh.uv_layers.get(active or "") is not None:
            mesh.uv_layers.active = mesh.uv_layers[active]
        if mesh.uv_layers.get(render or "") is not None:
            mesh.uv_layers[render].active_render = True


def _restore(mesh, backup):
    bm = bmesh.new()
    try:
        with _uv_map_choices_kept(mesh):
            bm.from_mesh(backup)
            bm.to_mesh(mesh)
    finally:
        bm.free()
    for name in (VERTEX_ID, FACE_ID):
        if mesh.attributes.get(name) is not None:
            mesh.attributes.remove(mesh.attributes[name])
    mesh.update()


def _rebuild(mesh, n, P, V, F, V2, cut, patch_faces, patch_tri, patch_source,
             face_layers, old_face_data, corner_layers, old_corner_data, tri_loops):
    """The BMesh round trip and the numpy writes after it; returns the new polygons."""
    # Ids 1.. on the mesh's own elements; the patch has no id layer, so its
    # elements read 0 afterwards (BMesh fills appended elements' layers with
    # defaults: it matches layers by type, not name, so the patch gets none).
    _set_ids(mesh, VERTEX_ID, "POINT", np.arange(1, n + 1))
    _set_ids(mesh, FACE_ID, "FACE", np.arange(1, P + 1))
    patch, used_old = _patch_mesh(V2, patch_faces, n)
    try:
        bm = bmesh.new()
        try:
            bm.from_mesh(mesh)
            bm.from_mesh(patch)  # appended after the mesh's own elements
            bm.verts.ensure_lookup_table()
            bm.faces.ensure_lookup_table()
            verts = bm.verts
            # The patch's copies of old vertices (right after the n old ones) onto the old ones.
            targetmap = dict(zip((verts[n + k] for k in range(len(used_old))),
                                 (verts[int(i)] for i in used_old)))
            doomed = [bm.faces[int(p)] for p in np.flatnonzero(cut)]
            bmesh.ops.weld_verts(bm, targetmap=targetmap)  # touches only patch faces
            # The cut polygons, and their edges and vertices no face uses any more.
            bmesh.ops.delete(bm, geom=[f for f in doomed if f.is_valid], context="FACES")
            with _uv_map_choices_kept(mesh):
                bm.to_mesh(mesh)
        finally:
            bm.free()
    finally:
        bpy.data.meshes.remove(patch)

    # Vertices: the old ones that stay keep their order, then the new ones in V2's
    # order (no vertex is created after one is deleted, so none moves up).
    vertex_ids = _get_ids(mesh, VERTEX_ID) - 1
    new_vertices = np.flatnonzero(vertex_ids < 0)
    if len(new_vertices) != len(V2) - n:
        raise PasteWriteError(f"{len(new_vertices)} new vertices written, {len(V2) - n} expected")
    vertex_ids[new_vertices] = np.arange(n, len(V2))
    mesh.vertices.foreach_set("co", V2[vertex_ids].astype(np.float32).ravel())
    # Faces: new ones found by their vertices (welding may have reordered them).
    face_ids = _get_ids(mesh, FACE_ID) - 1
    new_polygons = np.flatnonzero(face_ids < 0)
    face_ids[new_polygons] = P + _match_triangles(mesh, new_polygons, vertex_ids, patch_faces, len(V2))
    source = face_ids.copy()
    source[new_polygons] = patch_source[face_ids[new_polygons] - P]
    for layer, values in zip(face_layers, old_face_data):
        _write(mesh, layer, values[source])
    # Corners of the new faces (UVs, colours): interpolated in the triangle they
    # came from, at their position projected onto it.
    if corner_layers and len(new_polygons):
        loops, weights, corners = _new_corners(mesh, new_polygons, vertex_ids, V, F, V2,
                                               patch_tri[face_ids[new_polygons] - P], tri_loops)
        for layer, old in zip(corner_layers, old_corner_data):
            values = _read(mesh, layer)
            source_values = old[corners]                          # (k, 3 corners, 3 sources[, width])
            if layer[2] in (np.float32, np.float64):
                w = weights if source_values.ndim == 3 else weights[..., None]
                values[loops] = (w * source_values).sum(axis=2)
            else:                                                 # integers: the nearest corner's
                pick = weights.argmax(axis=2)
                values[loops] = np.take_along_axis(source_values, pick[..., None], axis=2)[..., 0]
            _write(mesh, layer, values)
    return new_polygons


def _match_triangles(mesh, polygons, vertex_ids, triangles, num_ids):
    """For each polygon (triangles, final numbering; vertex_ids maps to V2's), the
    row of `triangles` (V2 numbering) with the same three vertices."""
    if len(polygons) != len(triangles):
        raise PasteWriteError(f"{len(polygons)} new faces written, {len(triangles)} expected")
    loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", loop_start)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    if np.any(loop_total[polygons] != 3):
        raise PasteWriteError("a new face is not a triangle")
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    corners = vertex_ids[loop_vertex[loop_start[polygons, None] + np.arange(3)]]

    def keys(t):
        t = np.sort(np.asarray(t, dtype=np.int64), axis=1)
        return (t[:, 0] * num_ids + t[:, 1]) * num_ids + t[:, 2]

    wanted, have = keys(triangles), keys(corners)
    order = np.argsort(wanted)
    at = np.clip(np.searchsorted(wanted[order], have), 0, len(order) - 1)
    if not np.array_equal(wanted[order][at], have):
        raise PasteWriteError("a new face has no counterpart in the paste result")
    return order[at]

