"""The Repair option of the operators that need a closed genus-0 mesh (issue
19), inside real Blender: a mesh as artists bring it (a seam split, holes,
faces inside out, a loose part) is mended for the computation, the results
land on the user's own vertices and polygons, and nothing is added to the mesh."""
import bmesh
import bpy
import numpy as np
import pytest
from mathutils import Matrix

pytestmark = pytest.mark.usefixtures("addon_scene")


def coordinates(data):
    co = np.empty(3 * len(data), dtype=np.float32)
    data.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def messy_sphere():
    """A UV sphere with one meridian split (an unwelded seam), three faces
    deleted (holes), every face turned inside out, and a small loose cube."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    on_seam = lambda v: abs(v.co.y) < 1e-6 and v.co.x > 1e-6
    bmesh.ops.split_edges(bm, edges=[e for e in bm.edges if all(on_seam(v) for v in e.verts)])
    holes = [f for f in bm.faces if f.calc_center_median().x < -0.9 and abs(f.calc_center_median().z) < 0.3]
    assert len(holes) >= 2
    bmesh.ops.delete(bm, geom=holes[:3], context="FACES_ONLY")
    bmesh.ops.reverse_faces(bm, faces=list(bm.faces))
    bmesh.ops.create_cube(bm, size=0.2, matrix=Matrix.Translation((3.0, 0.0, 0.0)))
    bm.to_mesh(obj.data)
    bm.free()
    obj.data.update()
    return obj


def run_reported(capfd, op, **options):
    capfd.readouterr()
    status = op(**options)
    out, err = capfd.readouterr()
    return status, out + err


def test_sphere_map_repairs_a_messy_mesh_and_writes_back_onto_its_own_vertices(capfd):
    obj = messy_sphere()
    mesh = obj.data
    counts = (len(mesh.vertices), len(mesh.polygons))
    V = coordinates(mesh.vertices)
    status, report = run_reported(capfd, bpy.ops.paramorph.sphere_map)
    assert status == {"FINISHED"}
    assert (len(mesh.vertices), len(mesh.polygons)) == counts  # no fill faces added to the user's mesh
    for words in ("repaired", "merged", "filled", "inside-out", "removed 1 smaller part"):
        assert words in report, words
    key = coordinates(mesh.shape_keys.key_blocks["Sphere"].data)
    cube = V[:, 0] > 2.0
    np.testing.assert_allclose(key[cube], V[cube], atol=1e-6)  # the dropped part stays where it is
    centre = 0.5 * (V.min(axis=0) + V.max(axis=0))
    radii = np.linalg.norm(key[~cube] - centre, axis=1)
    assert np.ptp(radii) < 1e-4 * radii.mean()  # every vertex of the sphere part on the sphere
    # Both copies of a split seam vertex got the same place on the sphere.
    seam = np.flatnonzero((np.abs(V[:, 1]) < 1e-6) & (V[:, 0] > 1e-6))
    pairs = [(i, j) for i in seam for j in seam if i < j and np.linalg.norm(V[i] - V[j]) < 1e-6]
    assert pairs and all(np.allclose(key[i], key[j]) for i, j in pairs)
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    mesh.uv_layers["Sphere"].data.foreach_get("uv", uv)
    assert np.isfinite(uv).all()


def test_without_repair_the_error_says_what_is_wrong_and_offers_repair():
    obj = messy_sphere()
    with pytest.raises(RuntimeError, match=r"mesh has 13 vertices lying on other vertices \(seams split on "
                                           r"export\).*Merge by Distance, or turn on Repair"):
        bpy.ops.paramorph.sphere_map(repair=False)
    assert obj.data.shape_keys is None


def test_segment_extremities_labels_every_polygon_of_the_messy_mesh(capfd):
    obj = messy_sphere()
    status, report = run_reported(capfd, bpy.ops.paramorph.segment_extremities)
    assert status == {"FINISHED"} and "repaired" in report
    labels = np.empty(len(obj.data.polygons), dtype=np.int32)
    obj.data.attributes["paramorph_region"].data.foreach_get("value", labels)
    assert labels.min() >= 0 and labels.max() + 1 == obj.paramorph_regions


def test_a_handle_is_reported_as_something_repair_cannot_fix():
    bpy.ops.mesh.primitive_torus_add()
    with pytest.raises(RuntimeError, match="cannot remove handles"):
        bpy.ops.paramorph.sphere_map()


def select_pair(source, target):
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in (source, target))
    bpy.context.view_layer.objects.active = target


def messy_source_and_target():
    import make_samples
    source = messy_sphere()  # a UV sphere: it has a UV layer ("UVMap") to carry
    source.vertex_groups.new(name="Top").add([v.index for v in source.data.vertices if v.co.z > 0.3],
                                             1.0, "REPLACE")
    target = make_samples.build_octopus(subdivisions=3, limbs=4)
    target.location = (6.0, 0.0, 0.0)
    select_pair(source, target)
    return source, target


def test_morph_to_keeps_the_messy_source_topology_and_moves_every_seam_copy_together(capfd):
    source, target = messy_source_and_target()
    V = coordinates(source.data.vertices)
    status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="KEEP", in_betweens=2)
    assert status == {"FINISHED"}, report
    assert f"{source.name} repaired: merged" in report
    keys = source.data.shape_keys.key_blocks
    end = coordinates(keys[target.name].data)
    assert len(end) == len(V)
    cube = V[:, 0] > 2.0
    np.testing.assert_allclose(end[cube], V[cube], atol=1e-6)  # the part repair left out stays
    seam = np.flatnonzero((np.abs(V[:, 1]) < 1e-6) & (V[:, 0] > 1e-6))
    pairs = [(i, j) for i in seam for j in seam if i < j and np.linalg.norm(V[i] - V[j]) < 1e-6]
    assert pairs and all(np.allclose(end[i], end[j]) for i, j in pairs)  # the seam does not tear open
    assert np.ptp(end[~cube], axis=0).max() > 1.5 * np.ptp(V[~cube], axis=0).max()  # it became the octopus


def test_morph_to_a_merged_topology_carries_uvs_and_groups_from_the_mended_source(capfd):
    source, target = messy_source_and_target()
    status, report = run_reported(capfd, bpy.ops.paramorph.morph_to, topology="MERGED", in_betweens=0)
    assert status == {"FINISHED"}, report
    morph = bpy.context.view_layer.objects.active
    assert morph is not source and morph.data.shape_keys is not None
    uv = np.empty(2 * len(morph.data.loops), dtype=np.float32)
    morph.data.uv_layers["UVMap"].data.foreach_get("uv", uv)
    assert np.isfinite(uv).all() and uv.min() >= -1e-6 and uv.max() <= 1 + 1e-6
    assert "Top" in morph.vertex_groups


def test_preview_matches_stores_pairs_on_the_objects_own_vertices_and_a_pin_on_a_dropped_part_is_refused(capfd):
    source, target = messy_source_and_target()
    status, report = run_reported(capfd, bpy.ops.paramorph.preview_matches)
    assert status == {"FINISHED"}, report
    matches = bpy.context.scene.paramorph_matches
    for pair in matches.pairs:
        assert 0 <= pair.vertex_a < len(source.data.vertices) and 0 <= pair.vertex_b < len(target.data.vertices)
    cube_vertex = int(np.flatnonzero(coordinates(source.data.vertices)[:, 0] > 2.0)[0])
    assert bpy.ops.paramorph.add_pin(vertex_a=cube_vertex, vertex_b=0) == {"FINISHED"}
    with pytest.raises(RuntimeError, match="Repair leaves out"):
        bpy.ops.paramorph.morph_to(topology="MERGED")


def test_rank_similar_shapes_compares_a_messy_mesh_after_repair():
    import make_samples
    blob = make_samples.build_blob(subdivisions=3)
    messy = messy_sphere()
    for repair, comparable in ((False, False), (True, True)):
        bpy.context.view_layer.objects.active = blob
        assert bpy.ops.paramorph.rank_similar_shapes(repair=repair) == {"FINISHED"}
        listing = {item.object_name: item for item in bpy.context.scene.paramorph_similar}
        assert (listing[messy.name].distance >= 0) == comparable, listing[messy.name].note


def test_a_non_manifold_message_says_it_once():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    edge = next(e for e in bm.edges if len(e.link_faces) == 2)
    tip = bm.verts.new((5.0, 5.0, 5.0))
    bm.faces.new((edge.verts[0], edge.verts[1], tip))  # a fin: an edge with three faces
    bm.to_mesh(obj.data)
    bm.free()
    with pytest.raises(RuntimeError) as raised:
        bpy.ops.paramorph.sphere_map(repair=False)
    text = str(raised.value)
    assert text.count("not manifold") == 1 and "Non Manifold" in text, text
