"""The README demo, run inside `blender -b` by scripts/demo.sh:

    blender -b --factory-startup --python-exit-code 1 --python scripts/demo_blender.py -- [--out DIR]

Builds the sample objects of blend_samples/make_samples.py in one scene and
runs paramorph's operators on them as an artist would (the add-on enabled
with addon_utils, then bpy.ops.paramorph.*):

- closed Suzanne: Sphere Map ("Sphere" UV layer and shape key),
- pinned disc: Isometric Unwrap of all faces, pins kept,
- octopus: Segment Extremities,
- CAD part: Detect Feature Regions.

The segmented objects show their regions through the colour attribute the
operators write ("paramorph_region_color", active); the two parameterized
ones get a checker colour attribute computed from their UVs. The objects are
laid out side by side, saved to DIR/demo.blend, and rendered with Workbench
(Studio light, Attribute colour) to DIR/demo.png."""
import argparse
import os
import sys

import bpy
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
for path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    if path not in sys.path:
        sys.path.insert(0, path)

import addon_utils  # noqa: E402
import make_samples  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

CHECKER_ATTRIBUTE = "demo_uv_checker"
CHECKER_COLORS = np.array([[0.92, 0.92, 0.90, 1.0], [0.22, 0.24, 0.30, 1.0]], dtype=np.float32)


def enable_addon():
    if addon_utils.enable("paramorph", default_set=True) is None:
        raise RuntimeError("the paramorph add-on could not be enabled")
    from paramorph import native
    if native.native is None:
        raise RuntimeError(native.load_error)


def activate(obj):
    view_layer = bpy.context.view_layer
    for other in view_layer.objects:
        other.select_set(other is obj)
    view_layer.objects.active = obj


def uv_checker(obj, squares=8):
    """A per-corner colour attribute: a checker of the active UV layer, one
    flat colour per face (the cell of its UV centroid), made the active colour
    so Workbench shows the parameterization."""
    mesh = obj.data
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    poly_of_loop = np.repeat(np.arange(len(loop_total)), loop_total)
    uv = uv.reshape(-1, 2).astype(np.float64)
    centroid = np.stack([np.bincount(poly_of_loop, uv[:, k]) for k in (0, 1)], axis=1)
    cells = np.floor(centroid / loop_total[:, None] * squares).astype(np.int64)
    colors = CHECKER_COLORS[(cells[:, 0] + cells[:, 1]) % 2][poly_of_loop]
    attribute = mesh.attributes.new(name=CHECKER_ATTRIBUTE, type="BYTE_COLOR", domain="CORNER")
    attribute.data.foreach_set("color", colors.ravel())
    mesh.color_attributes.active_color = attribute
    mesh.update()


def sphere_map_suzanne():
    obj = make_samples.build_suzanne_closed()
    activate(obj)
    bpy.ops.paramorph.sphere_map()
    obj.data.uv_layers.active = obj.data.uv_layers["Sphere"]
    uv_checker(obj)
    return obj, "sphere map: UV layer 'Sphere' and shape key 'Sphere' (checker from the Sphere UVs)"


def unwrap_disc(max_iterations):
    obj = make_samples.build_pinned_disc()
    activate(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    try:
        bpy.ops.paramorph.isometric_unwrap(max_iterations=max_iterations)
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    uv_checker(obj, squares=4)
    return obj, f"isometric unwrap: UV layer '{obj.data.uv_layers.active.name}', pins kept"


def segment_octopus():
    obj = make_samples.build_octopus()
    activate(obj)
    bpy.ops.paramorph.segment_extremities()
    return obj, f"segment extremities: {obj.paramorph_regions} regions"


def segment_cad_part():
    obj = make_samples.build_cad_part()
    activate(obj)
    bpy.ops.paramorph.detect_feature_regions()
    return obj, f"feature regions: {obj.paramorph_regions} regions"


def world_corners(obj):
    M = np.array(obj.matrix_world)
    corners = np.array([tuple(c) for c in obj.bound_box], dtype=np.float64)
    return corners @ M[:3, :3].T + M[:3, 3]


def lay_out(objects, size=3.0, gap=1.0):
    """Each object scaled (object transform) to `size` across, standing on z = 0,
    side by side along x in the given order."""
    x = 0.0
    for obj in objects:
        obj.location = (0.0, 0.0, 0.0)
        obj.rotation_euler = (0.0, 0.0, 0.0)
        local = np.array([tuple(c) for c in obj.bound_box], dtype=np.float64)
        obj.scale = (size / (local.max(axis=0) - local.min(axis=0)).max(),) * 3
        bpy.context.view_layer.update()
        corners = world_corners(obj)
        low, high = corners.min(axis=0), corners.max(axis=0)
        obj.location = (x - low[0], -0.5 * (low[1] + high[1]), -low[2])
        x += (high[0] - low[0]) + gap
    bpy.context.view_layer.update()


def add_camera(objects, aspect, direction=(0.3, -1.0, 0.65), margin=1.08, corners=None):
    """An orthographic camera looking along -direction that frames every object
    (or the given world-space points)."""
    d = Vector(direction).normalized()
    rotation = (-d).to_track_quat("-Z", "Y").to_matrix()
    right, up = np.array(rotation.col[0]), np.array(rotation.col[1])
    if corners is None:
        corners = np.vstack([world_corners(o) for o in objects])
    r, u, depth = corners @ right, corners @ up, corners @ np.array(d)
    width, height = np.ptp(r), np.ptp(u)
    center = 0.5 * (r.min() + r.max()) * right + 0.5 * (u.min() + u.max()) * up
    camera = bpy.data.cameras.new("DemoCamera")
    camera.type = "ORTHO"
    camera.ortho_scale = margin * max(width, height * aspect)
    camera.clip_end = 1000.0
    obj = bpy.data.objects.new("DemoCamera", camera)
    bpy.context.scene.collection.objects.link(obj)
    location = center + (depth.max() + 10.0) * np.array(d)
    obj.matrix_world = Matrix.Translation(Vector(location)) @ rotation.to_4x4()
    bpy.context.scene.camera = obj
    return obj


def enum_pick(struct, prop, *choices):
    items = {item.identifier for item in struct.bl_rna.properties[prop].enum_items}
    return next(c for c in choices if c in items)


def set_up_render(scene, path, resolution):
    scene.render.engine = "BLENDER_WORKBENCH"
    shading = scene.display.shading
    shading.light = "STUDIO"
    # The active colour attribute: 'VERTEX' (shown as "Attribute") in 3.4 and 4.5.
    shading.color_type = enum_pick(shading, "color_type", "ATTRIBUTE", "VERTEX")
    shading.show_object_outline = True
    scene.display.render_aa = enum_pick(scene.display, "render_aa", "5", "8", "FXAA")
    scene.view_settings.view_transform = "Standard"  # region colours as written
    world = bpy.data.worlds.new("DemoWorld")
    world.color = (0.62, 0.64, 0.68)
    scene.world = world
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = path


def render_still(scene, png):
    """Renders the scene's current frame to `png`; RuntimeError when no file came out."""
    scene.render.filepath = png
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(png) or os.path.getsize(png) == 0:
        raise RuntimeError(f"the render wrote no {png}")


def start(prog, resolution, add_arguments=None):
    """Every demo's start: its command line after "--" (--out, created, and
    --resolution; add_arguments(parser) adds its own), then an empty scene
    with the add-on enabled. Returns (args, absolute output folder)."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog=prog)
    parser.add_argument("--out", default=os.path.join(REPO, "out"), help="output folder")
    parser.add_argument("--resolution", type=int, nargs=2, default=resolution, metavar=("W", "H"))
    if add_arguments is not None:
        add_arguments(parser)
    args = parser.parse_args(argv)
    out_dir = os.path.abspath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable_addon()
    return args, out_dir


def main():
    args, out_dir = start("demo_blender.py", (1280, 720), lambda parser: parser.add_argument(
        "--max-iterations", type=int, default=1000, help="unwrap iterations"))
    steps = [sphere_map_suzanne, lambda: unwrap_disc(args.max_iterations),
             segment_octopus, segment_cad_part]
    objects = []
    for step in steps:
        obj, summary = step()
        objects.append(obj)
        mesh = obj.data
        print(f"demo: {obj.name} ({len(mesh.vertices)} vertices, {len(mesh.polygons)} faces): "
              f"{summary}", flush=True)

    lay_out(objects)
    scene = bpy.context.scene
    add_camera(objects, args.resolution[0] / args.resolution[1])
    png = os.path.join(out_dir, "demo.png")
    blend = os.path.join(out_dir, "demo.blend")
    set_up_render(scene, png, args.resolution)
    bpy.ops.wm.save_as_mainfile(filepath=blend, check_existing=False)
    print(f"demo: wrote {blend}", flush=True)
    render_still(scene, png)
    print(f"demo: wrote {png} ({args.resolution[0]}x{args.resolution[1]}, Workbench)", flush=True)


if __name__ == "__main__":
    main()
