"""The "Paramorph" tab in the 3D View sidebar."""
import textwrap

import bpy

from . import jobs
from .native import load_error, native


class PARAMORPH_PT_main(bpy.types.Panel):
    bl_label = "Paramorph"
    bl_idname = "PARAMORPH_PT_main"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Paramorph"

    def draw(self, context):
        layout = self.layout
        if native is None:
            for i, line in enumerate(textwrap.wrap(load_error, 60)):
                layout.label(text=line, icon="ERROR" if i == 0 else "BLANK1")
            return
        settings = context.scene.paramorph
        for job in jobs.running():
            row = layout.row(align=True)
            row.label(text=f"{job.stage} {100 * job.fraction:.0f}%", icon="SORTTIME")
            row.operator("paramorph.cancel_jobs", text="", icon="CANCEL")
        obj = context.active_object
        if obj is None or obj.type != "MESH":  # what to do first
            layout.label(text="Select a mesh to start", icon="INFO")  # fits the default sidebar
        col = layout.column(align=True)
        col.label(text="Parameterize")
        col.operator("paramorph.sphere_map")
        row = col.row()
        row.enabled = context.mode == "EDIT_MESH"
        row.operator("paramorph.isometric_unwrap")
        col = layout.column(align=True)
        col.label(text="Segment")
        col.operator("paramorph.segment_extremities")
        col.operator("paramorph.detect_feature_regions")
        obj = context.active_object
        if obj is not None and obj.type == "MESH" and obj.paramorph_regions > 0:
            col.label(text=f"{obj.paramorph_regions} regions on {obj.name}")
            row = col.row(align=True)
            row.prop(settings, "region_index", text="")
            row.operator("paramorph.select_region", text="Select").region = settings.region_index
            row = col.row(align=True)
            row.operator("paramorph.grow_regions", text="Grow")
            row.operator("paramorph.shrink_regions", text="Shrink")
            col.prop(settings, "show_overlay")
        col = layout.column(align=True)
        col.label(text="Shape search")
        col.operator("paramorph.rank_similar_shapes")
        listing = context.scene.paramorph_similar
        if len(listing):
            col.label(text=f"Closest to {settings.similar_reference}:")
            for item in listing:
                row = col.row(align=True)
                op = row.operator("paramorph.select_object", text=item.object_name, emboss=False)
                op.name = item.object_name
                row.label(text=f"{item.distance:.3f}" if item.distance >= 0 else "n/a",
                          icon="NONE" if item.distance >= 0 else "ERROR")
        self.draw_morph(context, layout)
        self.draw_paste(context, layout)

    @staticmethod
    def draw_morph(context, layout):
        col = layout.column(align=True)
        col.label(text="Morph")
        if len(context.selected_objects) != 2:
            col.label(text="Select source, then target", icon="INFO")
        col.operator("paramorph.pick_pins", icon="PINNED")
        col.operator("paramorph.preview_matches", icon="VIEWZOOM")
        matches = context.scene.paramorph_matches
        if matches.source is not None and matches.target is not None:
            pins = sum(p.pin for p in matches.pairs)
            col.label(text=f"{matches.source.name} → {matches.target.name}")
            col.label(text=f"{pins} pin{'' if pins == 1 else 's'}, {len(matches.pairs) - pins} "
                           f"automatic pair{'' if len(matches.pairs) - pins == 1 else 's'}")
            draw_candidates(context, col, matches)
            col.template_list("PARAMORPH_UL_match_pairs", "", matches, "pairs", matches, "pair_index", rows=4)
            row = col.row(align=True)
            row.operator("paramorph.add_pin", text="Add Pin", icon="ADD")
            row.operator("paramorph.remove_pair", text="Remove", icon="REMOVE")
            row = col.row(align=True)
            row.operator("paramorph.clear_pins", text="Clear Pins", icon="UNPINNED")
            row.operator("paramorph.clear_matches", text="Clear", icon="X")
        col.operator("paramorph.morph_to")

    @staticmethod
    def draw_paste(context, layout):
        from . import feature_store
        col = layout.column(align=True)
        col.label(text="Cut and paste")
        row = col.row()
        row.enabled = context.mode == "EDIT_MESH"
        row.operator("paramorph.copy_feature")
        col.operator("paramorph.paste_feature")
        last = feature_store.latest()
        if last is None:
            col.label(text="No feature copied yet", icon="INFO")
        else:  # two short lines: one ran off the default sidebar width
            col.label(text=last.name, icon="PASTEDOWN")
            col.label(text=f"{last.get(feature_store.FACES, 0)} faces", icon="BLANK1")


def _wrapped(layout, text, width, icon="BLANK1"):
    for line in textwrap.wrap(text, width):
        layout.label(text=line, icon=icon)


def _score_text(candidate):
    return "rejected" if candidate.rejected else f"{candidate.score:.3g}"


def draw_candidates(context, layout, matches):
    """The chosen candidate ("Chosen: extremities", its score beside what no
    pairs scored, and what it paired) and, in a box that opens, every
    candidate with its score, or why it was rejected, so the user sees
    whether the automatic pairs beat no pairs."""
    if not len(matches.candidates):
        return
    # Characters a sidebar line holds (labels are cut in the middle, not wrapped).
    width = max(16, int(context.region.width / (7.0 * context.preferences.system.ui_scale)) - 5) \
        if context.region is not None else 40
    chosen = next((c for c in matches.candidates if c.chosen), None)
    none = next((c for c in matches.candidates if c.kind == "none"), None)
    if chosen is not None:
        layout.label(text=f"Chosen: {chosen.kind}", icon="CHECKMARK")
        versus = f" (none: {_score_text(none)})" if none is not None and chosen.kind != "none" else ""
        layout.label(text=f"score {_score_text(chosen)}{versus}", icon="BLANK1")
        _wrapped(layout, chosen.detail, width)
    box = layout.box()
    box.prop(matches, "show_candidates", emboss=False, text=f"Candidates ({len(matches.candidates)})",
             icon="TRIA_DOWN" if matches.show_candidates else "TRIA_RIGHT")
    if not matches.show_candidates:
        return
    column = box.column(align=True)
    for c in matches.candidates:
        split = column.split(factor=0.65, align=True)
        split.label(text=c.kind, icon="CHECKMARK" if c.chosen else ("CANCEL" if c.rejected else "DOT"))
        split.label(text=_score_text(c))
        _wrapped(column, c.detail + (f"; rejected: {c.rejected}" if c.rejected else ""), width)


class PARAMORPH_UL_match_pairs(bpy.types.UIList):
    """One row per pin or pair: pins (the pin icon and their number, as Morph
    To's messages number them: "pin 0") with editable source and target
    vertex indices; the automatic pairs read-only with the candidate they came
    from."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        if item.pin:
            number = sum(p.pin for p in data.pairs[:index])
            split = layout.split(factor=0.22, align=True)
            split.label(text=str(number), icon="PINNED")
            row = split.row(align=True)
            row.prop(item, "vertex_a", text="", emboss=True)
            row.prop(item, "vertex_b", text="", emboss=True)
        else:
            split = layout.split(factor=0.6, align=True)
            split.label(text=f"{item.vertex_a} → {item.vertex_b}", icon="DOT")
            split.label(text=item.kind or "pair")


class PARAMORPH_OT_select_object(bpy.types.Operator):
    """Make this object the active, only selected one"""
    bl_idname = "paramorph.select_object"
    bl_label = "Select Object"
    bl_options = {"REGISTER", "UNDO"}

    name: bpy.props.StringProperty()

    def execute(self, context):
        obj = context.scene.objects.get(self.name)
        if obj is None:
            self.report({"ERROR"}, f"no object named {self.name} in the scene")
            return {"CANCELLED"}
        if context.mode != "OBJECT":
            bpy.ops.object.mode_set(mode="OBJECT")
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


class PARAMORPH_OT_cancel_jobs(bpy.types.Operator):
    """Stop the running paramorph computation (like Esc); the mesh stays as it was"""
    bl_idname = "paramorph.cancel_jobs"
    bl_label = "Cancel Paramorph Computation"

    def execute(self, context):
        jobs.cancel_all()
        return {"FINISHED"}


classes = (PARAMORPH_OT_select_object, PARAMORPH_OT_cancel_jobs, PARAMORPH_UL_match_pairs, PARAMORPH_PT_main)
