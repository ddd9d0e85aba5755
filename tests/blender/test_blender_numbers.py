"""Mesh problems are named by Blender's own numbers (issue 20): on a quad
mesh the native validator sees loop triangles, whose numbers and diagonals
are not Blender's polygons and edges. Each case builds a quad mesh with one
known fault and checks the report names exactly the faulty elements."""
import contextlib
import re

import bmesh
import bpy
import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("addon_scene")


@contextlib.contextmanager
def editing(mesh):
    """A BMesh of `mesh`, written back when the block ends."""
    bm = bmesh.new()
    bm.from_mesh(mesh)
    yield bm
    bm.to_mesh(mesh)
    bm.free()


def quad_ball():
    """A closed all-quad ball (a subdivided cube), active and selected."""
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    obj = bpy.context.active_object
    with editing(obj.data) as bm:
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=3, use_grid_fill=True)
    assert all(p.loop_total == 4 for p in obj.data.polygons)
    return obj


def refused(op=None, **options):
    with pytest.raises(RuntimeError) as raised:
        (op or bpy.ops.paramorph.sphere_map)(repair=False, **options)
    return str(raised.value)


def numbers_after(text, word):
    match = re.search(rf"\b{word} ([\d, ]+(?: and \d+ more)?)", text)
    assert match, text
    return [int(n) for n in re.findall(r"\d+", match.group(1).split(" and ")[0])]


def edge_index(mesh, a, b):
    return next(e.index for e in mesh.edges if set(e.vertices) == {a, b})


def test_a_fin_on_a_quad_edge_names_the_blender_edge():
    obj = quad_ball()
    with editing(obj.data) as bm:
        bm.edges.ensure_lookup_table()
        edge = bm.edges[17]
        a, b = (v.index for v in edge.verts)
        tip1, tip2 = bm.verts.new((4.0, 4.0, 4.0)), bm.verts.new((4.0, 5.0, 4.0))
        bm.faces.new((edge.verts[0], edge.verts[1], tip2, tip1))  # a quad fin: three faces on one edge
    text = refused()
    assert text.count("not manifold") == 1 and "1 edge has more than two faces" in text, text
    assert numbers_after(text, "edge") == [edge_index(obj.data, a, b)], text
    assert "polygon" not in text, text


def test_a_duplicate_quad_names_the_blender_polygon_not_its_triangles():
    obj = quad_ball()
    mesh = obj.data
    V = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", V)
    polygons = [list(p.vertices) for p in mesh.polygons]
    copy = len(polygons)
    polygons.append(list(polygons[40]))  # the same four corners again (triangulated alike)
    doubled = bpy.data.meshes.new("doubled")
    doubled.from_pydata(V.reshape(-1, 3).tolist(), [], polygons)  # no validate(): it would drop the copy
    obj.data = doubled
    text = refused()
    assert "1 polygon on the same corners as another" in text, text
    assert numbers_after(text, "polygon") == [copy], text  # its triangles are 2*copy and 2*copy+1


def test_one_quad_turned_over_names_its_four_blender_edges():
    obj = quad_ball()
    with editing(obj.data) as bm:
        bm.faces.ensure_lookup_table()
        bmesh.ops.reverse_faces(bm, faces=[bm.faces[30]])
    text = refused(bpy.ops.paramorph.segment_extremities)
    expected = sorted(obj.data.polygons[30].edge_keys)
    expected = sorted(edge_index(obj.data, a, b) for a, b in expected)
    assert "point different ways across 4 edges" in text, text
    assert numbers_after(text, "edges") == expected, text
    assert "Recalculate Outside" in text, text


def test_a_problem_on_a_quad_diagonal_names_the_polygons_it_lies_in():
    # Two quads crossing on their shared diagonal 0-2: four triangles on one
    # triangle edge, but no Blender edge there to name.
    points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1), (0.5, 0.5, -1)]
    mesh = bpy.data.meshes.new("crossed")
    mesh.from_pydata(points, [], [(0, 1, 2, 3), (0, 4, 2, 5)])
    obj = bpy.data.objects.new("crossed", mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    assert not any({0, 2} == set(e.vertices) for e in mesh.edges)
    text = refused()
    assert "1 edge has more than two faces (inside polygons 0, 1)" in text, text


def test_zero_area_polygons_and_corners_on_a_line_are_told_apart():
    # A quad squashed flat has no area (Degenerate Dissolve); a quad with a
    # corner moved onto the line between two others has area, but one of its
    # triangles has none (Limited Dissolve removes that corner).
    for squash, words in ((True, "1 zero-area polygon"), (False, "1 polygon with a corner on a straight line")):
        bpy.ops.object.select_all(action="DESELECT")
        obj = quad_ball()
        mesh = obj.data
        polygon = mesh.polygons[21]
        a, b, c, d = (mesh.vertices[v].co.copy() for v in polygon.vertices)
        if squash:  # every corner onto the a-c diagonal
            mesh.vertices[polygon.vertices[1]].co = a.lerp(c, 0.4)
            mesh.vertices[polygon.vertices[3]].co = a.lerp(c, 0.6)
        else:  # b onto the straight line a-c: the a-b-c triangle has no area
            mesh.vertices[polygon.vertices[1]].co = a.lerp(c, 0.5)
        mesh.update()
        text = refused()
        assert words in text and numbers_after(text, "polygon") == [21], text
        bpy.data.objects.remove(obj)
