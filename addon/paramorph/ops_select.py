"""Selecting faces by region: a region under the mouse or by index, and
growing or shrinking the selection a region at a time. They read the
"paramorph_region" face attribute written by the segmentation operators."""
import bpy
import numpy as np

from . import bridge, poll_reasons, regions, view_ray


def _labels_or_report(operator, obj):
    """Call in Object Mode: in Edit Mode attribute layers live in the BMesh."""
    labels = regions.read_labels(obj.data)
    if labels is None:
        operator.report({"ERROR"}, f"{obj.name} has no regions: run Segment Extremities or "
                                   "Detect Feature Regions first")
    return labels


class _RegionSelection:
    @classmethod
    def poll(cls, context):
        return poll_reasons.one_mesh(cls, context)


class PARAMORPH_OT_select_region(_RegionSelection, bpy.types.Operator):
    """Select the faces of one region: the one under the mouse, or by index"""
    bl_idname = "paramorph.select_region"
    bl_label = "Select Region"
    bl_options = {"REGISTER", "UNDO"}

    region: bpy.props.IntProperty(name="Region", default=0, min=0)
    extend: bpy.props.BoolProperty(name="Extend", default=False,
                                   description="Add to the selection instead of replacing it")

    def execute(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj, face_select=True):
            labels = _labels_or_report(self, obj)
            if labels is None:
                return {"CANCELLED"}
            count = int(labels.max()) + 1 if len(labels) else 0
            if self.region >= count:
                self.report({"ERROR"}, f"{obj.name} has regions 0 to {count - 1}, not {self.region}")
                return {"CANCELLED"}
            mask = labels == self.region
            if self.extend:
                mask |= regions.selected_polygons(obj.data)
            regions.select_polygons(obj.data, mask)
        self.report({"INFO"}, f"Region {self.region}: {int((labels == self.region).sum())} faces")
        return {"FINISHED"}

    def invoke(self, context, event):
        obj = context.active_object
        if context.area is None or context.area.type != "VIEW_3D" or context.region is None:
            return self.execute(context)
        with bridge.object_mode(context, obj):
            labels = _labels_or_report(self, obj)
            polygon = None if labels is None else _polygon_under_mouse(context, obj, event)
        if labels is None:
            return {"CANCELLED"}
        if polygon is None:
            self.report({"WARNING"}, f"the mouse is not over {obj.name}")
            return {"CANCELLED"}
        self.region = int(labels[polygon])
        self.extend = event.shift
        return self.execute(context)


def _polygon_under_mouse(context, obj, event):
    ray = view_ray.mouse_ray(context, obj, event)
    if ray is None:
        return None
    hit, _, _, polygon = obj.ray_cast(*ray)
    return polygon if hit and polygon >= 0 else None


class _GrowShrink(_RegionSelection):
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj, face_select=True):
            labels = _labels_or_report(self, obj)
            if labels is None:
                return {"CANCELLED"}
            selected = regions.selected_polygons(obj.data)
            mask = self.change(obj.data, labels, selected)
            regions.select_polygons(obj.data, mask)
        self.report({"INFO"}, f"{len(np.unique(labels[mask]))} regions, {int(mask.sum())} faces selected")
        return {"FINISHED"}


class PARAMORPH_OT_grow_regions(_GrowShrink, bpy.types.Operator):
    """Complete the regions the selection touches; if they are complete, add their
    neighbouring regions"""
    bl_idname = "paramorph.grow_regions"
    bl_label = "Grow Selection by Regions"

    def change(self, mesh, labels, selected):
        return regions.grown(mesh, labels, selected)


class PARAMORPH_OT_shrink_regions(_GrowShrink, bpy.types.Operator):
    """Keep only the fully selected regions that do not border an unselected one"""
    bl_idname = "paramorph.shrink_regions"
    bl_label = "Shrink Selection by Regions"

    def change(self, mesh, labels, selected):
        return regions.shrunk(mesh, labels, selected)


classes = (PARAMORPH_OT_select_region, PARAMORPH_OT_grow_regions, PARAMORPH_OT_shrink_regions)
