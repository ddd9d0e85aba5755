"""Every operator as a user runs it, inside real Blender: on the sample
scenes, checking the data it writes, that undo and cancel restore the mesh,
and that bad input gives a report and changes nothing."""
import bpy
import numpy as np
import pytest

import make_samples
from paramorph import bridge, jobs, regions


pytestmark = pytest.mark.usefixtures("addon_scene")


def vertex_coordinates(mesh):
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def uv_array(mesh, name):
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    mesh.uv_layers[name].data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)


def mesh_state(mesh):
    """What an operator might change: UV layer names, shape keys, attributes, selection."""
    return (tuple(layer.name for layer in mesh.uv_layers),
            None if mesh.shape_keys is None else tuple(k.name for k in mesh.shape_keys.key_blocks),
            tuple(sorted(a.name for a in mesh.attributes if not a.name.startswith((".", "_")))),
            regions.selected_polygons(mesh).tobytes())


def test_operators_are_registered_and_searchable():
    for idname in ("sphere_map", "isometric_unwrap", "segment_extremities", "detect_feature_regions",
                   "select_region", "grow_regions", "shrink_regions", "rank_similar_shapes"):
        op = getattr(bpy.ops.paramorph, idname)
        rna = op.get_rna_type()
        assert rna.name and rna.description, idname  # F3 search shows name and tooltip
    for idname in ("sphere_map", "segment_extremities", "rank_similar_shapes", "isometric_unwrap"):
        # Both, or Blender shows no redo panel for the options (Repair, Apply Modifiers).
        assert {"REGISTER", "UNDO"} <= set(getattr(bpy.types, f"PARAMORPH_OT_{idname}").bl_options), idname
    assert hasattr(bpy.types, "PARAMORPH_PT_main")


def test_sphere_map_operator_writes_uv_and_shape_key():
    obj = make_samples.build_blob(subdivisions=3)
    assert bpy.ops.paramorph.sphere_map(weights="barycentric") == {"FINISHED"}
    mesh = obj.data
    assert "Sphere" in mesh.uv_layers and "Sphere" in mesh.shape_keys.key_blocks
    uv = uv_array(mesh, "Sphere")
    assert np.all(np.isfinite(uv)) and uv[:, 1].min() >= 0 and uv[:, 1].max() <= 1


def test_sphere_map_of_a_long_coiled_tube_is_fold_free_and_says_how(capfd):
    # Issue 28: before, "could not build a fold-free start" on such a mesh.
    import os
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(__file__)), "native"))
    import meshes
    V, F = meshes.coiled_tube()
    mesh = bpy.data.meshes.new("Coil")
    mesh.from_pydata(V.tolist(), [], F.tolist())
    obj = bpy.data.objects.new("Coil", mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    capfd.readouterr()
    assert bpy.ops.paramorph.sphere_map() == {"FINISHED"}
    out, err = capfd.readouterr()
    key = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.shape_keys.key_blocks["Sphere"].data.foreach_get("co", key)
    X = key.reshape(-1, 3).astype(np.float64) - 0.5 * (V.min(axis=0) + V.max(axis=0))  # about the box's centre
    X /= np.linalg.norm(X, axis=1, keepdims=True)
    det = np.einsum("ij,ij->i", X[F[:, 0]], np.cross(X[F[:, 1]], X[F[:, 2]]))
    assert (det > 0).all()  # the shape key holds the map (in float32): every face turned outward
    assert "laid out coarse to fine" in out + err, out + err  # Blender prints operator reports in -b


def test_sphere_map_in_edit_mode_returns_to_edit_mode():
    obj = make_samples.build_blob(subdivisions=3)
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.paramorph.sphere_map() == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    assert "Sphere" in obj.data.uv_layers


def test_open_mesh_reports_in_plain_words_and_changes_nothing():
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=6, y_subdivisions=6)
    obj = bpy.context.active_object
    before = mesh_state(obj.data)
    with pytest.raises(RuntimeError, match=r"mesh has 1 hole: close them \(Fill Holes\) first, or turn on Repair"):
        bpy.ops.paramorph.sphere_map(repair=False)
    assert mesh_state(obj.data) == before


def test_a_cancelled_run_leaves_the_mesh_as_it_was(monkeypatch):
    obj = make_samples.build_octopus(subdivisions=3)
    before = mesh_state(obj.data)
    # Esc in the modal operator sets the cancel flag; here the flag is set
    # before the first progress report, so the native call stops at once.
    monkeypatch.setattr(jobs.NativeJob, "_progress", lambda self, fraction, stage: False)
    assert bpy.ops.paramorph.segment_extremities() == {"CANCELLED"}
    assert bpy.ops.paramorph.sphere_map() == {"CANCELLED"}
    assert mesh_state(obj.data) == before


def test_the_job_runs_in_a_thread_and_stops_when_cancelled():
    obj = make_samples.build_octopus(subdivisions=4)
    V, F, _, _ = bridge.mesh_arrays(obj.data)
    pm = bridge.require_native()
    done = jobs.NativeJob(pm.sphere_map, V, F).start()
    assert done.wait(120) and done.error is None and done.result.flipped == 0
    assert done.fraction == 1.0
    stopped = jobs.NativeJob(pm.sphere_map, V, F)
    stopped.cancel()
    stopped.start().wait(120)
    assert isinstance(stopped.error, pm.Cancelled) and stopped.result is None


def test_segment_extremities_labels_every_tentacle(tmp_path):
    obj = make_samples.build_octopus(subdivisions=4, limbs=6)
    assert bpy.ops.paramorph.segment_extremities() == {"FINISHED"}
    labels = regions.read_labels(obj.data)
    assert labels is not None and labels.shape == (len(obj.data.polygons),)
    # One region per tentacle tip, another for the body's top.
    V = vertex_coordinates(obj.data)
    angles = 2 * np.pi * np.arange(6) / 6
    tips = [int(np.argmax(V[:, :2] @ np.array([np.cos(a), np.sin(a)]))) for a in angles]
    tips.append(int(np.argmax(V[:, 2])))
    loop_vertex = np.empty(len(obj.data.loops), dtype=np.int32)
    obj.data.loops.foreach_get("vertex_index", loop_vertex)
    loop_total = np.empty(len(obj.data.polygons), dtype=np.int32)
    obj.data.polygons.foreach_get("loop_total", loop_total)
    poly_of_loop = np.repeat(np.arange(len(loop_total)), loop_total)
    tip_regions = {int(labels[poly_of_loop[np.flatnonzero(loop_vertex == t)[0]]]) for t in tips}
    assert len(tip_regions) == 7, (tip_regions, labels.max() + 1)

    # The same regions as colours (Solid shading / Workbench show them).
    colors = np.empty(4 * len(obj.data.loops), dtype=np.float32)
    obj.data.attributes[regions.COLOR_ATTRIBUTE].data.foreach_get("color", colors)
    first_loop_color = colors.reshape(-1, 4)[np.cumsum(loop_total) - loop_total]
    for r in range(labels.max() + 1):
        assert len(np.unique(first_loop_color[labels == r], axis=0)) == 1
    assert len(np.unique(first_loop_color, axis=0)) == labels.max() + 1

    path = str(tmp_path / "octopus.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    np.testing.assert_array_equal(regions.read_labels(bpy.data.objects["Octopus"].data), labels)


def test_detect_feature_regions_on_the_cad_part():
    obj = make_samples.build_cad_part()
    assert bpy.ops.paramorph.detect_feature_regions() == {"FINISHED"}
    labels = regions.read_labels(obj.data)
    # Plate sides, top and bottom, boss walls and tops, rib faces: many flat
    # or smooth faces meeting at creases.
    assert labels.max() + 1 >= 10, labels.max() + 1
    # Every region is edge-connected... and faces across a 90 degree edge differ.
    points = np.empty(len(obj.data.vertices), dtype=np.int32)
    obj.data.attributes["paramorph_feature_point"].data.foreach_get("value", points)
    assert (points == -1).sum() >= 4  # the corners / tips on the hull
    assert set(np.unique(points)) <= {-1, 0, 1}


def test_select_grow_and_shrink_by_regions():
    obj = make_samples.build_octopus(subdivisions=3)
    assert bpy.ops.paramorph.segment_extremities() == {"FINISHED"}
    mesh = obj.data
    labels = regions.read_labels(mesh)
    assert bpy.ops.paramorph.select_region(region=1) == {"FINISHED"}
    np.testing.assert_array_equal(regions.selected_polygons(mesh), labels == 1)
    with pytest.raises(RuntimeError, match="has regions 0 to"):
        bpy.ops.paramorph.select_region(region=int(labels.max()) + 1)

    # Grow: a complete region gains its neighbours; shrink takes them back.
    assert bpy.ops.paramorph.grow_regions() == {"FINISHED"}
    grown = regions.selected_polygons(mesh)
    adjacency = regions.region_adjacency(mesh, labels)
    neighbours = set(adjacency[(adjacency == 1).any(axis=1)].ravel())
    np.testing.assert_array_equal(grown, np.isin(labels, list(neighbours | {1})))
    assert bpy.ops.paramorph.shrink_regions() == {"FINISHED"}
    shrunk = regions.selected_polygons(mesh)
    assert shrunk.sum() < grown.sum() and not (shrunk & ~grown).any()

    # In Edit Mode the selection shows there and the mode stays.
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.paramorph.select_region(region=0) == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    np.testing.assert_array_equal(regions.selected_polygons(mesh), labels == 0)


def test_select_region_without_regions_reports():
    make_samples.build_blob(subdivisions=2)
    with pytest.raises(RuntimeError, match="has no regions"):
        bpy.ops.paramorph.select_region(region=0)


def test_rank_similar_shapes_lists_the_same_shape_first():
    import mathutils
    reference = make_samples.build_octopus(name="Reference", subdivisions=4, limbs=6)
    # The same shape, finer and turned: the closest; a blob and a 3-limbed one further.
    twin = make_samples.build_octopus(name="Twin", subdivisions=5, limbs=6)
    twin.data.transform(mathutils.Matrix.Rotation(0.7, 4, "Z"))
    make_samples.build_blob(name="Blob", subdivisions=4)
    make_samples.build_octopus(name="Tripod", subdivisions=4, limbs=3)
    bpy.ops.mesh.primitive_torus_add()  # a handle (Repair cannot remove it): listed as not comparable
    torus = bpy.context.active_object
    bpy.context.view_layer.objects.active = reference
    assert bpy.ops.paramorph.rank_similar_shapes() == {"FINISHED"}
    listing = bpy.context.scene.paramorph_similar
    names = [item.object_name for item in listing]
    assert names[0] == "Twin", [(i.object_name, i.distance) for i in listing]
    assert names[-1] == torus.name and listing[len(listing) - 1].distance == -1.0
    assert "genus 1" in listing[len(listing) - 1].note
    distances = [item.distance for item in listing][:-1]
    assert distances == sorted(distances) and distances[0] < 0.5 * distances[1]

    bpy.context.view_layer.objects.active = torus
    with pytest.raises(RuntimeError, match="cannot remove handles"):
        bpy.ops.paramorph.rank_similar_shapes()


def test_rank_similar_shapes_compares_what_the_viewport_shows(capfd):
    # An octopus with a Cast modifier shows as a ball: with modifiers applied it
    # is compared as the ball it shows (close to the blob), without them as
    # the octopus it is underneath (issue 20: modifiers were silently ignored).
    reference = make_samples.build_blob(name="Reference", subdivisions=4)
    cast = make_samples.build_octopus(name="Cast", subdivisions=4, limbs=6)
    modifier = cast.modifiers.new("Cast", "CAST")
    modifier.cast_type, modifier.factor = "SPHERE", 1.0
    make_samples.build_octopus(name="Tripod", subdivisions=4, limbs=3)
    bpy.context.view_layer.objects.active = reference
    distance, said = {}, {}
    capfd.readouterr()
    for apply in (True, False):
        assert bpy.ops.paramorph.rank_similar_shapes(apply_modifiers=apply) == {"FINISHED"}
        distance[apply] = {i.object_name: i.distance for i in bpy.context.scene.paramorph_similar}
        said[apply] = capfd.readouterr().out
    assert 0 <= distance[True]["Cast"] < 0.5 * distance[False]["Cast"], distance
    # Off, it says which objects were compared without their modifiers; on, nothing to say.
    assert "Cast: computed on the mesh without its modifiers (Cast)" in said[False], said
    assert "without its modifiers" not in said[True], said


def test_segmentation_reuses_the_sphere_map_of_the_same_geometry(monkeypatch):
    from paramorph import sphere_cache
    sphere_cache.clear()
    obj = make_samples.build_octopus(subdivisions=3)
    assert bpy.ops.paramorph.sphere_map() == {"FINISHED"}
    calls = []
    pm = bridge.require_native()
    original = pm.segment_extremities
    monkeypatch.setattr(pm, "segment_extremities",
                        lambda *a, **k: calls.append("sphere" in k) or original(*a, **k))
    assert bpy.ops.paramorph.segment_extremities() == {"FINISHED"}
    # Moving a vertex changes the geometry: the map is computed afresh.
    co = vertex_coordinates(obj.data)
    co[0] *= 1.01
    obj.data.vertices.foreach_set("co", co.ravel())
    assert bpy.ops.paramorph.segment_extremities() == {"FINISHED"}
    assert calls == [True, False]


def test_the_backend_preference_chooses_where_the_solver_runs():
    prefs = bpy.context.preferences.addons["paramorph"].preferences
    assert prefs.backend == "auto"
    assert {"auto", "opencl", "cpu"} == {item.identifier for item in prefs.bl_rna.properties["backend"].enum_items}
    prefs.backend = "cpu"
    obj = make_samples.build_blob(subdivisions=3)
    from paramorph import sphere_cache
    sphere_cache.clear()
    reports = []
    pm = bridge.require_native()
    original = pm.sphere_map
    try:
        pm.sphere_map = lambda *a, **k: reports.append(k.get("backend")) or original(*a, **k)
        assert bpy.ops.paramorph.sphere_map() == {"FINISHED"}
    finally:
        pm.sphere_map = original
        prefs.backend = "auto"
    assert reports == ["cpu"]
    assert "Sphere" in obj.data.uv_layers


class _RecordingLayout:
    """Stands in for a UILayout: records what a menu's draw() puts in it."""

    def __init__(self):
        self.operators, self.menus = [], []

    def operator(self, idname, **_):
        self.operators.append(idname)

    def menu(self, idname, **_):
        self.menus.append(idname)

    def separator(self):
        pass


def test_one_paramorph_submenu_in_the_object_and_edit_mesh_menus():
    import types
    from paramorph import menus
    for host, entry, submenu in ((bpy.types.VIEW3D_MT_object, "_object_menu", menus.PARAMORPH_MT_object),
                                 (bpy.types.VIEW3D_MT_edit_mesh, "_edit_mesh_menu", menus.PARAMORPH_MT_edit_mesh)):
        names = [f.__name__ for f in host._dyn_ui_initialize()]
        assert names.count(entry) == 1 and "_menu_entries" not in names
        layout = _RecordingLayout()
        getattr(menus, entry)(types.SimpleNamespace(layout=layout), bpy.context)
        assert layout.menus == [submenu.bl_idname] and layout.operators == []
        layout = _RecordingLayout()
        submenu.draw(types.SimpleNamespace(layout=layout), bpy.context)
        assert layout.operators and submenu.bl_label == "Paramorph"
        for idname in layout.operators:  # every entry is a registered operator
            assert getattr(bpy.ops.paramorph, idname.split(".")[1]).get_rna_type().name


def test_a_modifier_is_named_as_left_out_of_the_computation(capfd):
    obj = make_samples.build_blob(subdivisions=3)
    obj.modifiers.new("Smooth It", "SUBSURF")
    capfd.readouterr()
    assert bpy.ops.paramorph.sphere_map() == {"FINISHED"}
    out, err = capfd.readouterr()
    assert "computed on the mesh without its modifiers (Smooth It); apply them first" in out + err


def test_sphere_map_is_computed_on_the_object_as_it_looks():
    # A sphere squashed by its object's scale is an ellipsoid on screen: the
    # conformal map of the ellipsoid differs from that of the sphere.
    obj = make_samples.build_blob(subdivisions=3)
    assert bpy.ops.paramorph.sphere_map(shape_key=False) == {"FINISHED"}
    plain = uv_array(obj.data, "Sphere")
    obj.scale = (1.0, 1.0, 0.2)
    bpy.context.view_layer.update()
    assert bpy.ops.paramorph.sphere_map(shape_key=False) == {"FINISHED"}
    squashed = uv_array(obj.data, "Sphere")
    assert np.abs(squashed - plain).max() > 0.01


def test_a_greyed_operator_says_why():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    with pytest.raises(RuntimeError, match="Select a mesh object first"):
        bpy.ops.paramorph.sphere_map()
    make_samples.build_blob(subdivisions=2)
    with pytest.raises(RuntimeError, match=r"Works in Edit Mode: press Tab"):
        bpy.ops.paramorph.isometric_unwrap()
    with pytest.raises(RuntimeError, match=r"Select two mesh objects: click the source, then Shift\+click the target "
                                           r"\(1 selected now\)"):
        bpy.ops.paramorph.morph_to()
    with pytest.raises(RuntimeError, match="There are no pins to clear"):
        bpy.ops.paramorph.clear_pins()


def test_the_status_bar_says_how_long_is_left():
    from paramorph.native_operator import remaining_words
    assert remaining_words(1.0, 0.5) == ""      # too early to say
    assert remaining_words(30.0, 0.01) == ""    # too little done to say
    assert remaining_words(10.0, 0.5) == "  about 10 s left"
    assert remaining_words(120.0, 0.5) == "  about 2 min left"


JARGON = ("genus", "l-bfgs", "log area stretch", "polyharmonic", "wendland", "barycentric", "conformal",
          "face floor", "lindstrom")


def test_tooltips_speak_artist_words_first():
    # Technical terms may follow in parentheses, after the plain words (issue 20).
    import re
    for idname in dir(bpy.ops.paramorph):
        rna = getattr(bpy.ops.paramorph, idname).get_rna_type()
        texts = [rna.name, rna.description]
        for prop in rna.properties:
            texts += [prop.name, prop.description]
            texts += [f"{item.name} {item.description}" for item in getattr(prop, "enum_items", ())]
        for text in texts:
            plain = re.sub(r"\([^)]*\)", "", text or "").lower()
            for word in JARGON:
                assert word not in plain, f"{idname}: {text!r}"


def test_long_runs_are_estimated_from_the_face_count_before_they_start(monkeypatch):
    from paramorph import run_time
    monkeypatch.setattr(run_time, "_rates", dict(run_time._rates))  # what it learns stays in this test
    # A 97k-face morph (source and target together ~190k faces) is announced
    # in minutes; a small sphere map is not announced at all.
    morph = run_time.estimate("Morph To", 190_000)
    assert morph > 40 and "(estimated from the face count)" in run_time.notice("Morph To", 190_000, 50_000)
    assert run_time.notice("Sphere Map", 20_000, 50_000) == ""
    # Over the large-input threshold it is said even when quick, with the count.
    assert run_time.notice("Sphere Map", 60_000, 50_000).startswith("Sphere Map: 60,000 faces: about")
    # Finished runs teach the rate: on a machine four times as slow the next
    # estimate doubles (halfway, geometrically), the one after nears four times.
    before = run_time.estimate("Morph To", 80_000)
    run_time.learn("Morph To", 40_000, 4 * run_time.estimate("Morph To", 40_000))
    assert run_time.estimate("Morph To", 80_000) == pytest.approx(2 * before)
    run_time.learn("Morph To", 100, 50.0)  # tiny runs measure overheads: ignored
    run_time.learn("Morph To", 80_000, 0.2)  # so do runs under a second (a cached map)
    assert run_time.estimate("Morph To", 80_000) == pytest.approx(2 * before)
    run_time.learn("Morph To", 80_000, 4 * before)
    assert run_time.estimate("Morph To", 80_000) == pytest.approx(2 ** 1.5 * before)
    assert run_time.duration_words(5400) == "about 1.5 h" and run_time.duration_words(12) == "about 10 s"


def test_the_overlay_forgets_an_object_whose_geometry_changed():
    # The viewport overlay caches its batches per object; a depsgraph update of
    # the geometry (an edit, Recalculate Normals, a new segmentation) drops
    # them, so the next redraw shows the mesh as it is now (issue 20). The
    # handler is added only with a window; here it is added by hand.
    from paramorph import overlay
    obj = make_samples.build_octopus(subdivisions=3)
    other = make_samples.build_blob(name="Other", subdivisions=2)
    bpy.context.view_layer.objects.active = obj
    other.select_set(False)  # only the octopus goes into Edit Mode
    obj.select_set(True)
    assert bpy.ops.paramorph.segment_extremities() == {"FINISHED"}
    bpy.app.handlers.depsgraph_update_post.append(overlay._forget_updated)
    try:
        overlay._cache[obj.name] = overlay._cache[other.name] = ("cached", None)
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.mesh.normals_make_consistent(inside=True)  # the normals turned inwards
        bpy.ops.object.mode_set(mode="OBJECT")
        bpy.context.view_layer.update()
        assert obj.name not in overlay._cache and other.name in overlay._cache
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(overlay._forget_updated)
        overlay._cache.clear()
