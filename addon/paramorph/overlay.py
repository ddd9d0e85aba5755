"""Viewport overlay: the active mesh's regions as translucent colours,
region borders as lines and feature points as dots, drawn by a `gpu` draw
handler from the "paramorph_region" and "paramorph_feature_point"
attributes; the morph's pins and previewed pairs (a dot on each object
joined by a line; pins white and larger); and, while Pick Pins runs, the
vertex under the mouse and the half-picked pin. Shader names are the plain
built-ins that exist from Blender 3.4 to 5.x (no bgl, no 3D_ prefixed
names)."""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from . import regions
from .morph import pin_store

_handler = None
# object name -> (mesh pointer, batches). Built once per geometry: a
# depsgraph update of the object (an edit, a new segmentation) drops its
# entry, so a redraw reads no mesh data.
_cache = {}


def _key(obj):
    return obj.data.as_pointer()


def forget(name):
    """Drop the object's batches (its regions were rewritten)."""
    _cache.pop(name, None)


def _forget_updated(scene, depsgraph):
    for update in depsgraph.updates:
        if update.is_updated_geometry:  # objects come with their own name
            _cache.pop(update.id.name, None)


def _batches(obj):
    mesh = obj.data
    labels = regions.read_labels(mesh)
    if labels is None:
        return None
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    mesh.calc_loop_triangles()
    tris = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    tri_poly = np.empty(len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", tri_poly)
    # Lift the overlay off the surface a little so it does not z-fight, to
    # both sides: where the normals point inwards (a file exported inside
    # out) the outward copy is the one seen (issue 20: the horse's regions
    # were only visible in X-ray); the other hides behind the surface.
    normals = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("normal", normals)
    size = float(np.linalg.norm(co.max(axis=0) - co.min(axis=0))) if len(co) else 1.0
    lift = 2e-3 * size * normals.reshape(-1, 3)
    lifted, sunk = co + lift, co - lift

    colors = regions.region_colors(int(labels.max()) + 1, alpha=0.45)
    corner_color = np.repeat(colors[labels[tri_poly]], 3, axis=0)
    shader = gpu.shader.from_builtin("SMOOTH_COLOR")
    faces = batch_for_shader(shader, "TRIS", {"pos": np.concatenate([lifted[tris], sunk[tris]]),
                                              "color": np.concatenate([corner_color, corner_color])})

    loop_edge = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", loop_edge)
    edge_vertices = np.empty(2 * len(mesh.edges), dtype=np.int32)
    mesh.edges.foreach_get("vertices", edge_vertices)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    poly_of_loop = np.repeat(np.arange(len(loop_total)), loop_total)
    # Border edges: edges whose two polygons carry different labels.
    label_of_loop = labels[poly_of_loop]
    edge_min = np.full(len(mesh.edges), np.iinfo(np.int32).max, dtype=np.int64)
    edge_max = np.full(len(mesh.edges), -1, dtype=np.int64)
    np.minimum.at(edge_min, loop_edge, label_of_loop)
    np.maximum.at(edge_max, loop_edge, label_of_loop)
    border = np.flatnonzero((edge_max >= 0) & (edge_min != edge_max))
    ends = edge_vertices.reshape(-1, 2)[border].ravel()
    lines = np.concatenate([lifted[ends], sunk[ends]])
    line_shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    borders = batch_for_shader(line_shader, "LINES", {"pos": lines}) if len(border) else None

    points = None
    attribute = mesh.attributes.get(regions.FEATURE_POINT_ATTRIBUTE)
    if attribute is not None and attribute.domain == "POINT":
        kinds = np.empty(len(mesh.vertices), dtype=np.int32)
        attribute.data.foreach_get("value", kinds)
        marked = np.flatnonzero(kinds != 0)
        if len(marked):
            colors = np.where(kinds[marked, None] > 0, [[0.1, 0.3, 1.0, 1.0]], [[1.0, 0.9, 0.1, 1.0]])
            colors = colors.astype(np.float32)
            points = batch_for_shader(shader, "POINTS", {"pos": np.concatenate([lifted[marked], sunk[marked]]),
                                                         "color": np.concatenate([colors, colors])})
    return shader, faces, line_shader, borders, points


def tag_redraw(context):
    for area in context.screen.areas if context.screen else ():
        if area.type == "VIEW_3D":
            area.tag_redraw()


def _draw_regions(obj):
    cached = _cache.get(obj.name)
    if cached is None or cached[0] != _key(obj):
        cached = (_key(obj), _batches(obj))
        _cache[obj.name] = cached
    if cached[1] is None:
        return
    shader, faces, line_shader, borders, points = cached[1]
    gpu.matrix.push()
    gpu.matrix.multiply_matrix(obj.matrix_world)
    shader.bind()
    faces.draw(shader)
    if borders is not None:
        gpu.state.line_width_set(2.0)
        line_shader.bind()
        line_shader.uniform_float("color", (0.05, 0.05, 0.05, 0.9))
        borders.draw(line_shader)
        gpu.state.line_width_set(1.0)
    if points is not None:
        gpu.state.point_size_set(8.0)
        shader.bind()
        points.draw(shader)
        gpu.state.point_size_set(1.0)
    gpu.matrix.pop()


def _world_points(obj, vertices):
    """World positions of a few vertices (a pair list, not the whole mesh)."""
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    co = np.array([obj.data.vertices[i].co for i in vertices], dtype=np.float64).reshape(-1, 3)
    return (co @ matrix[:3, :3].T + matrix[:3, 3]).astype(np.float32)


def _draw_matches(matches):
    """The previewed pairs: a dot on each object, the two joined by a line, one
    colour per pair; pins white and larger."""
    source, target = matches.source, matches.target
    pairs = [(p.vertex_a, p.vertex_b, p.pin) for p in matches.pairs
             if p.vertex_a < len(source.data.vertices) and p.vertex_b < len(target.data.vertices)]
    if not pairs:
        return
    a = _world_points(source, [p[0] for p in pairs])
    b = _world_points(target, [p[1] for p in pairs])
    pin = np.array([p[2] for p in pairs])
    colors = regions.region_colors(len(pairs))
    colors[pin] = (1.0, 1.0, 1.0, 1.0)
    shader = gpu.shader.from_builtin("SMOOTH_COLOR")
    ends = np.empty((2 * len(pairs), 3), dtype=np.float32)
    ends[0::2], ends[1::2] = a, b
    line_colors = np.repeat(colors, 2, axis=0)
    line_colors[:, 3] = 0.6
    gpu.state.depth_test_set("NONE")  # pairs stay visible through the surfaces
    shader.bind()
    batch_for_shader(shader, "LINES", {"pos": ends, "color": line_colors}).draw(shader)
    for size, chosen in ((9.0, ~pin), (14.0, pin)):
        if chosen.any():
            gpu.state.point_size_set(size)
            both = np.vstack([a[chosen], b[chosen]])
            batch_for_shader(shader, "POINTS", {"pos": both, "color": np.vstack([colors[chosen]] * 2)}).draw(shader)
    gpu.state.point_size_set(1.0)


HOVER_COLOR = (1.0, 0.85, 0.1, 1.0)     # the vertex under the mouse
PENDING_COLOR = (1.0, 0.45, 0.05, 1.0)  # the half-picked pin
OUTLINE_COLOR = (0.0, 0.0, 0.0, 1.0)


def _draw_picking(marks):
    """Pick Pins: the pending half (orange) joined to the vertex under the
    mouse (yellow) when that is on the other object; both ringed in black."""
    shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    gpu.state.depth_test_set("NONE")
    shader.bind()
    hover, pending = marks["hover"], marks["pending"]
    if hover is not None and pending is not None and marks["hover_side"] != marks["pending_side"]:
        gpu.state.line_width_set(2.0)
        shader.uniform_float("color", PENDING_COLOR)
        batch_for_shader(shader, "LINES", {"pos": np.array([pending, hover], dtype=np.float32)}).draw(shader)
        gpu.state.line_width_set(1.0)
    for position, color, size in ((pending, PENDING_COLOR, 14.0), (hover, HOVER_COLOR, 12.0)):
        if position is None:
            continue
        batch = batch_for_shader(shader, "POINTS", {"pos": np.array([position], dtype=np.float32)})
        for ring, ring_color in ((size + 6.0, OUTLINE_COLOR), (size, color)):
            gpu.state.point_size_set(ring)
            shader.uniform_float("color", ring_color)
            batch.draw(shader)
    gpu.state.point_size_set(1.0)


def draw():
    context = bpy.context
    scene = context.scene
    if scene is None or not getattr(scene, "paramorph", None):
        return
    picker = pin_store.active_picker
    show = scene.paramorph.show_overlay
    if not show and picker is None:
        return
    shown = []
    matches = getattr(scene, "paramorph_matches", None)
    previewing = matches is not None and matches.source is not None and matches.target is not None
    if previewing:
        shown += [matches.source, matches.target]
    obj = context.active_object
    if obj is not None and obj not in shown:
        shown.append(obj)
    gpu.state.blend_set("ALPHA")
    gpu.state.depth_test_set("LESS_EQUAL")
    for obj in shown if show else ():
        if obj.type == "MESH" and obj.mode != "EDIT" and obj.paramorph_regions > 0 and obj.visible_get():
            _draw_regions(obj)
    if previewing and len(matches.pairs):
        _draw_matches(matches)
    if picker is not None:
        try:
            marks = picker.marks()
        except ReferenceError:  # its objects were deleted under it
            marks = None
        if marks is not None:
            _draw_picking(marks)
    gpu.state.depth_test_set("NONE")
    gpu.state.blend_set("NONE")


def register():
    global _handler
    if _handler is None and not bpy.app.background:
        _handler = bpy.types.SpaceView3D.draw_handler_add(draw, (), "WINDOW", "POST_VIEW")
        bpy.app.handlers.depsgraph_update_post.append(_forget_updated)


def unregister():
    global _handler
    if _handler is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handler, "WINDOW")
        if _forget_updated in bpy.app.handlers.depsgraph_update_post:
            bpy.app.handlers.depsgraph_update_post.remove(_forget_updated)
        _handler = None
    _cache.clear()


classes = ()
