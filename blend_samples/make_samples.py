"""Builds the sample scenes (run inside Blender):

    blender -b --factory-startup --python blend_samples/make_samples.py -- [OUT_DIR]

Each builder returns the new object so scripts and tests can import them."""
import os
import sys

import bpy
import numpy as np


def _apply_all_modifiers(obj):
    bpy.context.view_layer.objects.active = obj
    for modifier in list(obj.modifiers):
        bpy.ops.object.modifier_apply(modifier=modifier.name)


def _coordinates(mesh):
    """Vertex positions as float64 (n, 3) (float32 foreach_get: a plain copy)."""
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def build_suzanne_closed(name="SuzanneClosed", voxel_size=0.045):
    """Suzanne made closed and genus 0: voxel remesh (fills the eye holes and
    welds the parts into one surface), then triangulated."""
    bpy.ops.mesh.primitive_monkey_add(size=2.0)
    obj = bpy.context.active_object
    obj.name = name
    remesh = obj.modifiers.new("Remesh", "REMESH")
    remesh.mode = "VOXEL"
    remesh.voxel_size = voxel_size
    obj.modifiers.new("Triangulate", "TRIANGULATE")
    _apply_all_modifiers(obj)
    return obj


def build_blob(name="Blob", subdivisions=5):
    """A generated closed genus-0 blob: an icosphere with a smooth radial bump field."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    obj = bpy.context.active_object
    obj.name = name
    mesh = obj.data
    P = _coordinates(mesh)
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    r = 1.0 + 0.25 * np.sin(3 * P[:, 0]) * np.cos(2 * P[:, 1]) + 0.35 * P[:, 2] ** 2
    mesh.vertices.foreach_set("co", (P * r[:, None] * [1.0, 1.4, 0.9]).astype(np.float32).ravel())
    mesh.update()
    return obj


def build_octopus(name="Octopus", subdivisions=5, limbs=6, faces=None):
    """An octopus-like blob: an icosphere with `limbs` tentacles pulled out
    around the equator, each bent slightly down (closed, genus 0). With
    `faces`, the icosphere is decimated to about that many triangles first
    (irregular triangles, like a scan)."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    obj = bpy.context.active_object
    obj.name = name
    if faces is not None and faces < len(obj.data.polygons):
        decimate = obj.modifiers.new("Decimate", "DECIMATE")
        decimate.ratio = faces / len(obj.data.polygons)
        _apply_all_modifiers(obj)
    mesh = obj.data
    P = _coordinates(mesh)
    P /= np.linalg.norm(P, axis=1, keepdims=True)
    angles = 2 * np.pi * np.arange(limbs) / limbs
    dirs = np.stack([np.cos(angles), np.sin(angles), np.full(limbs, -0.35)], axis=1)
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    pull = np.clip((P @ dirs.T - 0.9) / 0.1, 0.0, None).max(axis=1)
    out = P * (1.0 + 2.2 * pull[:, None] ** 1.5)
    out[:, 2] -= 0.3 * pull ** 2  # tentacles droop
    mesh.vertices.foreach_set("co", out.astype(np.float32).ravel())
    mesh.update()
    return obj


def _plate(name):
    """A 3 x 2 x 0.3 box centred at the origin, its scale applied."""
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    plate = bpy.context.active_object
    plate.name = name
    plate.scale = (3.0, 2.0, 0.3)
    bpy.ops.object.transform_apply(scale=True)
    return plate


def _union(obj, tool):
    """obj becomes obj united with tool (exact Boolean where the Blender has it); tool is deleted."""
    union = obj.modifiers.new("Union", "BOOLEAN")
    union.operation = "UNION"
    union.object = tool
    if hasattr(union, "solver"):
        union.solver = "EXACT"
    _apply_all_modifiers(obj)
    bpy.data.objects.remove(tool, do_unlink=True)


def build_cad_part(name="CadPart"):
    """A CAD-like part: a plate with two cylindrical bosses and two ribs,
    unioned into one closed manifold and triangulated."""
    plate = _plate(name)
    tools = []
    for x in (-0.9, 0.9):
        bpy.ops.mesh.primitive_cylinder_add(vertices=32, radius=0.35, depth=0.6, location=(x, 0.4, 0.35))
        tools.append(bpy.context.active_object)
    for y in (-0.55, -0.15):
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, y, 0.3))
        rib = bpy.context.active_object
        rib.scale = (2.4, 0.12, 0.5)
        tools.append(rib)
    for tool in tools:
        _union(plate, tool)
    plate.modifiers.new("Triangulate", "TRIANGULATE")
    _apply_all_modifiers(plate)
    return plate


def build_boss_plate(name="BossPlate", voxel_size=0.05):
    """The paste sample's source: a CAD-like plate (3 x 2 x 0.3) with one
    cylindrical boss (radius 0.35, 0.3 high) on top at (-0.6, 0, 0.15),
    welded into one closed manifold surface by a voxel remesh (even quads,
    enough faces for the boss's detail). The boss and a ring of plate around
    its foot are the faces within BOSS_BALL of its top's centre."""
    plate = _plate(name)
    bpy.ops.mesh.primitive_cylinder_add(vertices=48, radius=0.35, depth=0.3, location=(-0.6, 0.0, 0.3))
    _union(plate, bpy.context.active_object)
    remesh = plate.modifiers.new("Remesh", "REMESH")
    remesh.mode = "VOXEL"
    remesh.voxel_size = voxel_size
    _apply_all_modifiers(plate)
    return plate


# (centre x, y, z, radius) of the ball around the boss whose faces make the feature:
# the boss's top, its wall and a ring of the plate around its foot.
BOSS_BALL = (-0.6, 0.0, 0.6, 0.7)


def build_curved_target(name="CurvedTarget", subdivisions=5, radius=1.6):
    """The paste sample's target: a smooth closed surface curved everywhere,
    an icosphere squashed a little (radii 1.6, 1.6, 1.3)."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=radius)
    obj = bpy.context.active_object
    obj.name = name
    mesh = obj.data
    P = _coordinates(mesh) * [1.0, 1.0, 1.3 / radius]
    mesh.vertices.foreach_set("co", P.astype(np.float32).ravel())
    mesh.update()
    bpy.ops.object.shade_smooth()
    return obj


def build_paste_pair():
    """The paste sample: the boss plate (source) and the curved target side by side."""
    source = build_boss_plate()
    target = build_curved_target()
    source.location = (-2.6, 0.0, 0.0)
    target.location = (1.8, 0.0, 0.0)
    return source, target


def write_uvs_and_pins(mesh, uv, pins):
    """Per-loop UVs (L, 2) and pinned flags (L,) into the "UVMap" layer (made
    if missing, then active)."""
    layer = mesh.uv_layers.get("UVMap") or mesh.uv_layers.new(name="UVMap")
    mesh.uv_layers.active = layer
    if hasattr(layer, "pin"):  # 3.5+: the attribute API; on 4.5 the old
        # MeshUVLoop "pin_uv" foreach_set corrupts the heap (checked)
        layer.uv.foreach_set("vector", uv.astype(np.float32).ravel())
        if hasattr(layer, "pin_ensure"):  # 5.x: layer.pin stays empty until
            layer.pin_ensure()            # the pin attribute is made
        layer.pin.foreach_set("value", pins)
    else:
        layer.data.foreach_set("uv", uv.astype(np.float32).ravel())
        layer.data.foreach_set("pin_uv", pins)
    mesh.update()


def build_pinned_disc(name="PinnedDisc", subdivisions=12):
    """A bumpy disc (a grid cut to a circle and lifted) with a UV layer whose
    four boundary extremes are pinned at the corners of the unit square."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=subdivisions, y_subdivisions=subdivisions, size=2.0)
    obj = bpy.context.active_object
    obj.name = name
    mesh = obj.data
    P = _coordinates(mesh)
    r = np.maximum(np.abs(P[:, 0]), np.abs(P[:, 1]))
    scale = np.divide(r, np.hypot(P[:, 0], P[:, 1]), out=np.ones_like(r), where=r > 0)
    P[:, :2] *= scale[:, None]  # square rings -> circles
    P[:, 2] = 0.25 * np.sin(2.5 * P[:, 0]) * np.cos(2.0 * P[:, 1])
    mesh.vertices.foreach_set("co", P.astype(np.float32).ravel())
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    uv = 0.5 + 0.5 * P[loop_vertex, :2]
    pinned_vertices = [int(np.argmax(P[:, 0])), int(np.argmin(P[:, 0])),
                       int(np.argmax(P[:, 1])), int(np.argmin(P[:, 1]))]
    pins = np.isin(loop_vertex, pinned_vertices)
    # primitive_grid_add already made a "UVMap" (its own grid UVs): write
    # into that one, so the pins are on the active layer the unwrap uses.
    write_uvs_and_pins(mesh, uv, pins)
    return obj


def build_morph_pair(voxel_size=0.08, subdivisions=4):
    """The morph sample: a closed Suzanne (source) and a blob (target) of
    unrelated triangulations, side by side; select Suzanne, then the blob,
    and run Morph To."""
    source = build_suzanne_closed(voxel_size=voxel_size)
    target = build_blob(subdivisions=subdivisions)
    source.location = (-1.6, 0.0, 0.0)
    target.location = (1.6, 0.0, 0.0)
    view_layer = bpy.context.view_layer
    for obj in view_layer.objects:
        obj.select_set(obj in (source, target))
    view_layer.objects.active = target
    return source, target


BUILDERS = {
    "suzanne_closed": build_suzanne_closed,
    "octopus": build_octopus,
    "cad_part": build_cad_part,
    "pinned_disc": build_pinned_disc,
    "morph_pair": build_morph_pair,
    "paste_pair": build_paste_pair,
}


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    for name, builder in BUILDERS.items():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        builder()
        path = os.path.join(out_dir, f"{name}.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        print(f"wrote {path}")


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    main(os.path.abspath(args[0] if args else os.path.dirname(os.path.abspath(__file__))))
