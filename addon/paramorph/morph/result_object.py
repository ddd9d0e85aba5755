"""The morph as a Blender object (thesis 4.4): a new mesh on the merged
topology whose Basis is the source and whose shape keys go to the target
through in-between keys (as rigid as possible, issue 17), with the source's
materials, smooth shading, UV layers, colour attributes and vertex groups
carried over.
One property, the object's "paramorph_morph" (0 to 1), drives the chain of
keys and is keyframed over a frame range, so scrubbing plays the in-betweens
in order. numpy and foreach_set throughout, except for reading vertex group
memberships, which Blender offers per vertex only."""
import bpy
import numpy as np

from .. import bridge
from .job import key_times

# The object's custom property that drives the keys: 0 source, 1 target.
MORPH_PROPERTY = "paramorph_morph"


def _build_mesh(name, positions, faces):
    mesh = bpy.data.meshes.new(name)
    n, k = len(positions), len(faces)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(positions, dtype=np.float32).ravel())
    mesh.loops.add(3 * k)
    mesh.loops.foreach_set("vertex_index", np.ascontiguousarray(faces, dtype=np.int32).ravel())
    mesh.polygons.add(k)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * k, 3, dtype=np.int32))
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:  # read-only from 3.6
        mesh.polygons.foreach_set("loop_total", np.full(k, 3, dtype=np.int32))
    mesh.update(calc_edges=True)
    mesh.validate()
    return mesh


def _polygon_values(mesh, name, dtype):
    values = np.empty(len(mesh.polygons), dtype=dtype)
    mesh.polygons.foreach_get(name, values)
    return values


class _Extra:
    """Faces of the source copied as they are after the merged ones (its
    separate parts riding along): their polygons and loops in the source."""

    def __init__(self, poly=None, loops=None):
        self.poly = np.zeros(0, dtype=np.int64) if poly is None else np.asarray(poly)
        self.loops = np.zeros((0, 3), dtype=np.int64) if loops is None else np.asarray(loops).reshape(-1, 3)


def _carry_source_looks(source_mesh, mesh, result, tri_poly, tri_loops, extra=_Extra()):
    """Materials, smooth shading and every UV layer of the source, through
    the merged faces' source triangles and corner barycentrics; the `extra`
    faces' straight from their own polygons and loops."""
    source_poly = np.concatenate([tri_poly[np.asarray(result.source_face_a)], extra.poly])
    for material in source_mesh.materials:
        mesh.materials.append(material)
    if len(source_mesh.materials):
        mesh.polygons.foreach_set("material_index",
                                  _polygon_values(source_mesh, "material_index", np.int32)[source_poly])
    smooth = _polygon_values(source_mesh, "use_smooth", bool)[source_poly]
    mesh.polygons.foreach_set("use_smooth", smooth)
    for layer in source_mesh.uv_layers:
        uv = np.empty(2 * len(source_mesh.loops), dtype=np.float32)
        if hasattr(layer, "uv"):
            layer.uv.foreach_get("vector", uv)
        else:
            layer.data.foreach_get("uv", uv)
        corners = uv.reshape(-1, 2)[tri_loops.ravel()]  # rows 3t + c
        carried = np.asarray(result.carry(0, corners.astype(np.float64)))
        own = uv.reshape(-1, 2)[extra.loops.ravel()]
        bridge.write_uv_layer(mesh, np.concatenate([carried, own]), layer.name)
    if source_mesh.uv_layers.active is not None:
        mesh.uv_layers.active = mesh.uv_layers[source_mesh.uv_layers.active.name]
    _carry_colors(source_mesh, mesh, result, tri_loops, extra)


def _carry_vertex_groups(source, obj, result, tri_loops, extra_vertices=()):
    """The source's vertex groups on the merged vertices: each weight
    interpolated over the face of the source holding the merged vertex (0
    where a vertex is in no group), then on the `extra_vertices` of the
    source copied after them as they are. Empty groups are made too, so a
    rig that names them finds them."""
    if not source.vertex_groups:
        return
    mesh = source.data
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    faces = loop_vertex[tri_loops]  # the triangles the morph was given
    if result.inside_out_a:
        faces = faces[:, [0, 2, 1]]  # as the morph turned them
    merged = result.merged
    corners = faces[np.asarray(merged.face_a)]  # (M, 3) source vertices around each merged vertex
    bary = np.asarray(merged.bary_a)
    weights = np.zeros((len(source.vertex_groups), len(mesh.vertices)))
    for vertex in mesh.vertices:  # sparse memberships: no foreach_get for them
        for membership in vertex.groups:
            if membership.group < len(weights):
                weights[membership.group, vertex.index] = membership.weight
    for index, group in enumerate(source.vertex_groups):
        carried = np.round((bary * weights[index][corners]).sum(axis=1), 6)
        carried = np.concatenate([carried, weights[index][np.asarray(extra_vertices, dtype=np.int64)]])
        out = obj.vertex_groups.new(name=group.name)
        members = np.flatnonzero(carried > 0)
        values, which = np.unique(carried[members], return_inverse=True)
        batches = np.split(members[np.argsort(which, kind="stable")], np.cumsum(np.bincount(which))[:-1])
        for value, batch in zip(values, batches):  # one add() per distinct weight
            out.add(batch.tolist(), float(value), "REPLACE")
    obj.vertex_groups.active_index = source.vertex_groups.active_index


def _carry_colors(source_mesh, mesh, result, tri_loops, extra=_Extra()):
    """Colour attributes of the source (per corner or per vertex) as per-corner
    colours of the merged faces, then of the `extra` faces; the active one
    stays active."""
    if not hasattr(source_mesh, "color_attributes"):  # 3.2+
        return
    loop_vertex = np.empty(len(source_mesh.loops), dtype=np.int32)
    source_mesh.loops.foreach_get("vertex_index", loop_vertex)
    active = source_mesh.color_attributes.active_color
    for attribute in source_mesh.color_attributes:
        if attribute.domain not in ("CORNER", "POINT"):
            continue
        values = np.empty(4 * len(attribute.data), dtype=np.float32)
        attribute.data.foreach_get("color", values)
        values = values.reshape(-1, 4)
        per_loop = values if attribute.domain == "CORNER" else values[loop_vertex]
        carried = np.asarray(result.carry(0, per_loop[tri_loops.ravel()].astype(np.float64)))
        carried = np.concatenate([carried, per_loop[extra.loops.ravel()]])
        out = mesh.color_attributes.new(attribute.name, "FLOAT_COLOR", "CORNER")
        out.data.foreach_set("color", np.ascontiguousarray(carried, dtype=np.float32).ravel())
        if active is not None and attribute.name == active.name:
            mesh.color_attributes.active_color = out


def _fcurves(id_data):
    """An ID's F-curves, before and after slotted actions (4.4+)."""
    action = id_data.animation_data.action
    if hasattr(action, "fcurves") and not hasattr(id_data.animation_data, "action_slot"):
        return action.fcurves
    from bpy_extras import anim_utils
    return anim_utils.action_get_channelbag_for_slot(action, id_data.animation_data.action_slot).fcurves


def drive_keys(obj, keys):
    """Each key after Basis at full weight at its time on the morph property
    and at 0 at its neighbours' times (tent drivers, simple expressions that
    need no Python), so the shape passes through every key in order."""
    if MORPH_PROPERTY not in obj:
        obj[MORPH_PROPERTY] = 0.0
    ui = obj.id_properties_ui(MORPH_PROPERTY)
    ui.update(min=0.0, max=1.0, soft_min=0.0, soft_max=1.0,
              description="Paramorph: how far the morph has gone (0 source, 1 target)")
    count = len(keys)
    for i, key in enumerate(keys, start=1):
        key.driver_remove("value")
        driver = key.driver_add("value").driver
        driver.type = "SCRIPTED"
        variable = driver.variables.new()
        variable.name = "morph"
        variable.type = "SINGLE_PROP"
        variable.targets[0].id_type = "OBJECT"
        variable.targets[0].id = obj
        variable.targets[0].data_path = f'["{MORPH_PROPERTY}"]'
        driver.expression = f"max(0.0, 1.0 - abs(morph * {count} - {i}))"


def _animate(obj, frame_start, frame_end, easing):
    """The morph property from 0 at frame_start to 1 at frame_end; with
    `easing` it starts and ends slowly (Bezier), else linearly."""
    path = f'["{MORPH_PROPERTY}"]'
    if obj.animation_data is not None and obj.animation_data.action is not None:
        curves = _fcurves(obj)
        for curve in [c for c in curves if c.data_path == path]:  # an earlier morph's timing
            curves.remove(curve)
    for frame, value in ((frame_start, 0.0), (frame_end, 1.0)):
        obj[MORPH_PROPERTY] = value
        obj.keyframe_insert(path, frame=frame)
    obj[MORPH_PROPERTY] = 0.0
    for curve in _fcurves(obj):
        if curve.data_path != path:
            continue
        for point in curve.keyframe_points:
            point.interpolation = "BEZIER" if easing else "LINEAR"
            if easing:
                point.handle_left_type = point.handle_right_type = "AUTO_CLAMPED"
        curve.update()


def build(context, name, source, result, target_positions, shapes, *, tri_poly, tri_loops,
          target_name="Target", frame_start=1, frame_end=48, easing=True, source_positions=None,
          parts=None, source_triangles=None):
    """A new object `name` on the merged topology of `result` (paramorph_native.Morph),
    placed like `source` and linked to its collections: Basis = result.source,
    keys "<target_name> 25%"... (the in-between `shapes`, evenly spaced) and
    `target_name` = target_positions, driven by the object's morph property,
    which is keyframed from frame_start to frame_end. source_positions: the
    Basis in the source object's coordinates (default result.source).
    parts: the source's separate parts riding along (job.RidingParts,
    with their positions), added after the merged mesh as they are in the
    source, with their own looks and vertex groups; source_triangles: (polygon
    per triangle, loops per triangle, vertices per triangle) of the source's
    own triangulation, which parts.triangles index. Returns the object."""
    source_positions = np.asarray(result.source if source_positions is None else source_positions)
    faces = np.asarray(result.faces)
    extra, extra_vertices = _Extra(), np.zeros(0, dtype=np.int64)
    if parts is not None:
        # The separate parts; a stray vertex of the body Repair left out
        # would be a loose vertex here (the merged mesh is the body).
        rows = np.flatnonzero(parts.separate[parts.part_of])
        extra_vertices = parts.vertices[rows]
        own_poly, own_loops, own_faces = source_triangles
        number = np.full(max(int(np.max(own_faces)), int(np.max(parts.vertices))) + 1, -1, dtype=np.int64)
        number[extra_vertices] = len(source_positions) + np.arange(len(rows))
        own = number[np.asarray(own_faces)[parts.triangles]]
        # Not among stray vertices, and nothing mesh.validate() would drop
        # (a repeated corner, the same face twice): the looks are per face.
        whole = (own >= 0).all(axis=1) & (own[:, 0] != own[:, 1]) & (own[:, 1] != own[:, 2]) & \
            (own[:, 2] != own[:, 0])
        first = np.zeros(len(own), dtype=bool)
        first[np.unique(np.sort(own, axis=1), axis=0, return_index=True)[1]] = True
        whole &= first
        faces = np.concatenate([faces, own[whole]])
        source_positions = np.concatenate([source_positions, parts.basis[rows]])
        target_positions = np.concatenate([target_positions, parts.shapes[-1][rows]])
        shapes = [np.concatenate([shape, own[rows]]) for shape, own in zip(shapes, parts.shapes[:-1])]
        triangles = parts.triangles[whole]
        extra = _Extra(np.asarray(own_poly)[triangles], np.asarray(own_loops)[triangles])
    mesh = _build_mesh(name, source_positions, faces)
    _carry_source_looks(source.data, mesh, result, tri_poly, tri_loops, extra)
    obj = bpy.data.objects.new(name, mesh)
    _carry_vertex_groups(source, obj, result, tri_loops, extra_vertices)
    for collection in source.users_collection or (context.collection,):
        collection.objects.link(obj)
    obj.matrix_world = source.matrix_world.copy()
    add_morph_keys(context, obj, shapes, target_positions, target_name=target_name, frame_start=frame_start,
                   frame_end=frame_end, easing=easing)
    return obj


def _morph_keys(obj):
    """Names of the object's keys driven by its morph property (an earlier
    morph, to this target or another: one property drives one morph)."""
    keys = obj.data.shape_keys
    if keys is None or keys.animation_data is None:
        return set()
    names = set()
    for curve in keys.animation_data.drivers:
        if any(t.id == obj and t.data_path == f'["{MORPH_PROPERTY}"]'
               for v in curve.driver.variables for t in v.targets):
            names.add(curve.data_path.split('"')[1])
    return names


def add_morph_keys(context, obj, shapes, target_positions, *, target_name="Target", frame_start=1, frame_end=48,
                   easing=True):
    """Keep-topology morph: keys "<target_name> 11%"... (the in-between
    `shapes`) and `target_name` (target_positions), (#vertices, 3) in the
    object's own coordinates, added to `obj` itself relative to its Basis
    (made from the mesh when it has none) and driven by its morph property,
    keyframed from frame_start to frame_end. An earlier morph's keys (driven by
    the property, or named after this target) and timing are replaced; nothing
    else on the object changes."""
    with bridge.object_mode(context, obj):
        stale = _morph_keys(obj) | {target_name} | \
            {k.name for k in (obj.data.shape_keys.key_blocks if obj.data.shape_keys else ())
             if k.name.startswith(target_name + " ") and k.name.endswith("%")}
        stale = [obj.data.shape_keys.key_blocks[name] for name in stale
                 if obj.data.shape_keys and name in obj.data.shape_keys.key_blocks]
        for key in stale:
            key.driver_remove("value")
            obj.shape_key_remove(key)
        if obj.data.shape_keys is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        keys = []
        for t, shape in zip(key_times(len(shapes)), list(shapes) + [target_positions]):
            key_name = target_name if t == 1.0 else f"{target_name} {round(100 * t)}%"
            keys.append(bridge.add_shape_key(obj, shape, key_name))
        drive_keys(obj, keys)
        _animate(obj, frame_start, frame_end, easing)
