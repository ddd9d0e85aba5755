"""Segmentation operators: Segment Extremities (thesis 3.5.1) and Detect
Feature Regions (4.5). Both store the regions as the integer face attribute
"paramorph_region" (kept on save, read by the overlay and the selection
tools), as the colour attribute "paramorph_region_color" (shown by Solid
shading with Attribute colour and by Workbench renders, no overlay needed),
and feature points in "paramorph_feature_point" (per vertex: +1 concave,
-1 convex, 0 none)."""
import bpy
import numpy as np

from . import bridge, overlay, regions, repair_mesh, sphere_cache
from .native import native
from .native_operator import NativeOperator

class _Segmenter(NativeOperator):
    def prepare(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj):  # Edit Mode keeps the data in a BMesh
            V, F, tri_poly, _ = bridge.mesh_arrays(obj.data, polygons=True)
        repair = getattr(self, "repair", False)
        V = bridge.as_placed(V, obj)  # as the scene shows it (rotation, scale)
        state = {"arrays": (V, F), "object": obj.name, "tri_poly": tri_poly, "repaired": repair,
                 "objects": [obj.name]}
        function = repair_mesh.repaired_call(self.native_call()) if repair else self.native_call()
        return function, (V, F), self.native_options(V, F), state

    def finish(self, context, result, state):
        obj = bpy.data.objects[state["object"]]
        fixed, result = result if state["repaired"] else (None, result)
        segmentation = result[0] if isinstance(result, tuple) else result
        triangle_labels = np.asarray(segmentation.face_labels)
        if fixed is not None:
            triangle_labels = fixed.face_labels_to_input(triangle_labels)
        labels = regions.polygon_labels(obj.data, triangle_labels, state["tri_poly"])
        with bridge.object_mode(context, obj):
            regions.write_labels(obj.data, labels)
            regions.write_label_colors(obj.data, labels)
            if isinstance(result, tuple):
                points = result[1]
                regions.write_feature_points(obj.data, points.vertices, points.kinds)
        obj.paramorph_regions = int(labels.max()) + 1 if len(labels) else 0
        overlay.forget(obj.name)
        for area in context.screen.areas if context.screen else ():
            area.tag_redraw()
        return repair_mesh.with_summary(self.summary(result, obj.paramorph_regions), fixed)


def _segment_extremities(V, F, *, progress, **options):
    """native.segment_extremities on the conformal map Sphere Map just computed
    on this geometry (after a repair: on the repaired one), if any."""
    sphere = sphere_cache.get(sphere_cache.key(V, F, "conformal"))
    if sphere is not None:
        options["sphere"] = sphere
    return native.segment_extremities(V, F, progress=progress, **options)


class PARAMORPH_OT_segment_extremities(_Segmenter, bpy.types.Operator):
    """Split the active mesh into its body and the parts that stick out (limbs, ears, tail),
    by how much its sphere map shrinks them (a closed, sphere-like surface; Repair mends
    one that is not)"""
    bl_idname = "paramorph.segment_extremities"
    bl_label = "Segment Extremities"
    bl_options = {"REGISTER", "UNDO"}

    threshold: bpy.props.FloatProperty(
        name="Threshold", default=1.5, min=0.05, soft_max=5.0,
        description="How much more a part must stick out than the body to become its own region (higher: "
                    "fewer, longer parts; the rise of log area stretch of the sphere map)")
    min_area: bpy.props.FloatProperty(
        name="Minimum Area", default=0.01, min=0.0, max=0.5, subtype="FACTOR",
        description="Regions under this share of the surface are merged into a neighbour")

    repair: repair_mesh.REPAIR_PROPERTY

    def native_call(self):
        return _segment_extremities

    def native_options(self, V, F):
        return {"threshold": self.threshold, "min_area": self.min_area}

    def summary(self, result, count):
        return f"Segment Extremities: {count} regions"


def _feature_regions_and_points(V, F, *, progress, spacing, **options):
    """Feature regions, then their feature points, from one concavity."""
    concavity = native.concavity(V, F)
    segmentation = native.feature_regions(V, F, concavity=concavity, progress=progress, **options)
    points = native.feature_points(V, F, segmentation.face_labels, concavity, spacing=spacing)
    return segmentation, points


class FeatureRegionSettings:
    """The feature-region options (thesis 4.5) shared by Detect Feature Regions
    and Preview Matches; feature_options() gives them as the module's keywords."""
    normal_angle: bpy.props.FloatProperty(
        name="Crease Angle", default=0.6981317, min=0.0175, max=3.14159, subtype="ANGLE",
        description="Edges sharper than this separate regions")
    concavity_threshold: bpy.props.FloatProperty(
        name="Pocket Depth", default=0.02, min=0.001, max=0.5, subtype="FACTOR",
        description="Depth below the convex hull (share of the bounding-box diagonal) "
                    "that makes a pocket its own region")
    min_area: bpy.props.FloatProperty(
        name="Minimum Area", default=0.005, min=0.0, max=0.5, subtype="FACTOR",
        description="Regions under this share of the surface are merged into a neighbour")
    spacing: bpy.props.FloatProperty(
        name="Point Spacing", default=0.05, min=0.0, max=1.0, subtype="FACTOR",
        description="Closest two feature points of one kind in a region "
                    "(share of the bounding-box diagonal)")

    def feature_options(self):
        return {"normal_angle": float(np.degrees(self.normal_angle)),
                "concavity_threshold": self.concavity_threshold,
                "min_area": self.min_area, "spacing": self.spacing}


class PARAMORPH_OT_detect_feature_regions(_Segmenter, FeatureRegionSettings, bpy.types.Operator):
    """Split the active mesh into feature regions by creases and concavity, and mark
    feature points (pocket bottoms, tips)"""
    bl_idname = "paramorph.detect_feature_regions"
    bl_label = "Detect Feature Regions"
    bl_options = {"REGISTER", "UNDO"}


    def native_call(self):
        return _feature_regions_and_points

    def native_options(self, V, F):
        return self.feature_options()

    def summary(self, result, count):
        return f"Detect Feature Regions: {count} regions, {len(result[1].vertices)} feature points"


classes = (PARAMORPH_OT_segment_extremities, PARAMORPH_OT_detect_feature_regions)
