"""The live preview of Paste Feature: the faces the paste adds or moves,
drawn over the mesh by a `gpu` draw handler while the modal tool runs (the
mesh itself is only written on confirm). Shaded by a fixed light so the
feature's relief shows; edges as a thin wire."""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

_handler = None
_batches = None   # (faces, wire) batches of the current preview
_matrix = None    # the object's world matrix


def changed_faces(V, V2, F2, new_faces, num_untouched):
    """Rows of F2 to show: the new faces and the untouched ones whose vertices moved."""
    n = len(V)
    moved = np.zeros(len(V2), dtype=bool)
    moved[:n] = np.any(V2[:n] != V, axis=1)
    untouched = F2[:num_untouched]
    moved_rows = np.flatnonzero(moved[untouched].any(axis=1))
    return np.concatenate([moved_rows, np.asarray(new_faces, dtype=np.int64)])


def build(matrix_world, V, V2, F2, new_faces, num_untouched):
    """Prepares the batches for (V2, F2) (object space; the matrix places them)."""
    global _batches, _matrix
    rows = changed_faces(V, V2, F2, new_faces, num_untouched)
    tris = F2[rows]
    P = V2[tris].astype(np.float32)                      # (k, 3, 3) flat-shaded corners
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-30)
    light = np.array([0.3, -0.5, 0.8], dtype=np.float32)
    light /= np.linalg.norm(light)
    shade = 0.35 + 0.65 * np.abs(normal @ light)
    color = np.empty((len(rows), 4), dtype=np.float32)
    color[:, 0], color[:, 1], color[:, 2], color[:, 3] = 1.0 * shade, 0.62 * shade, 0.2 * shade, 0.9
    shader = gpu.shader.from_builtin("SMOOTH_COLOR")
    faces = batch_for_shader(shader, "TRIS", {"pos": P.reshape(-1, 3),
                                              "color": np.repeat(color, 3, axis=0)})
    edges = P[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 3)
    line_shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    wire = batch_for_shader(line_shader, "LINES", {"pos": edges})
    _batches = (shader, faces, line_shader, wire)
    _matrix = matrix_world.copy()
    return len(rows)


def _draw():
    if _batches is None:
        return
    shader, faces, line_shader, wire = _batches
    gpu.matrix.push()
    gpu.matrix.multiply_matrix(_matrix)
    gpu.state.depth_test_set("LESS_EQUAL")
    gpu.state.blend_set("ALPHA")
    shader.bind()
    faces.draw(shader)
    line_shader.bind()
    line_shader.uniform_float("color", (0.1, 0.05, 0.0, 0.35))
    wire.draw(line_shader)
    gpu.state.blend_set("NONE")
    gpu.state.depth_test_set("NONE")
    gpu.matrix.pop()


def start():
    global _handler
    if _handler is None and not bpy.app.background:
        _handler = bpy.types.SpaceView3D.draw_handler_add(_draw, (), "WINDOW", "POST_VIEW")


def stop():
    global _handler, _batches
    if _handler is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handler, "WINDOW")
        _handler = None
    _batches = None
