"""Isometric Unwrap (thesis ch. 2): the selected faces, cut at seams, mapped
to the plane with minimal stretch and no folds; Blender's pinned UVs are hard
constraints and stay exactly where they are. Writes the active UV layer
(creates "UVMap" when the mesh has none), only on the selected faces."""
import re

import bpy
import numpy as np

from . import bridge, poll_reasons, uv_patch
from .native import native
from .native_operator import NativeOperator, UserError
from .preferences import backend


def _map_islands(islands, *, progress, max_iterations, backend, margin, densities=None):
    """One isometric_map per island; progress spread over them. densities:
    per island, None (its pins are hard constraints) or the UV length per 3D
    length to size it by (its pins then place and turn it: uv_patch.place_by_pins).
    Returns (UVs, native results, largest pin offset per island)."""
    results, stats, offsets = [], [], []
    for i, island in enumerate(islands):
        def island_progress(fraction, stage, i=i):
            return progress((i + fraction) / len(islands), f"island {i + 1}/{len(islands)}: {stage}")
        density = densities[i] if densities is not None else None
        kwargs = {}
        if len(island.pinned) and density is None:
            kwargs = {"pinned": island.pinned, "pinned_uv": island.pinned_uv}
        m = native.isometric_map(island.V, island.F, max_iterations=max_iterations,
                                 backend=backend, progress=island_progress, **kwargs)
        uv, offset = np.asarray(m.uv), 0.0
        if len(island.pinned) and density is not None:
            uv, offset = uv_patch.place_by_pins(uv, island, density)
        results.append(uv)
        stats.append(m)
        offsets.append(offset)
    return uv_patch.pack_free_islands(results, islands, margin), stats, offsets


def _count(n, word):
    return f"{n} {word}{'' if n == 1 else 's'}"


def _require_discs(islands):
    """UserError, before any work, when seams leave islands the flattening
    cannot take: closed pieces or pieces with handles (a closed horse
    unwrapped without seams ran 46 s, then spoke of pinned UVs)."""
    closed = handles = 0
    for island in islands:
        report = native.validate(island.V, island.F)
        if report.boundary_loops == 0:
            closed += 1
        elif report.genus != 0:
            handles += 1
    if closed or handles:
        parts = []
        if closed:
            parts.append(f"{_count(closed, 'island')} {'is' if closed == 1 else 'are'} closed (no seam cuts "
                         "it open)")
        if handles:
            parts.append(f"{_count(handles, 'island')} still {'has' if handles == 1 else 'have'} a handle "
                         "(a loop around it has no seam)")
        raise UserError(f"the seams do not cut the selection into flat pieces: {' and '.join(parts)} of "
                        f"{len(islands)}; mark more seams (Edge > Mark Seam), e.g. one from each closed "
                        "piece's top to its bottom")


def distortion_words(stats):
    """'area distortion 12 %, worst stretch 31 %' over the islands (thesis
    ch. 2 measures: the spread of area ratios and the largest L2 stretch)."""
    area = max(max(m.metrics["area_max"] - 1.0, 1.0 - m.metrics["area_min"]) for m in stats)
    stretch = max(m.metrics["l2_max"] for m in stats) - 1.0
    return f"area distortion {100 * area:.0f} %, worst stretch {100 * max(stretch, 0.0):.0f} %"


class PARAMORPH_OT_isometric_unwrap(NativeOperator, bpy.types.Operator):
    """Unwrap the selected faces with minimal stretch and no folds, keeping pinned
    UVs exactly in place (seams cut the surface)"""
    bl_idname = "paramorph.isometric_unwrap"
    bl_label = "Isometric Unwrap"
    bl_options = {"REGISTER", "UNDO"}
    constraints = "uv"  # its ConstraintErrors are about pinned UVs

    max_iterations: bpy.props.IntProperty(
        name="Iterations", default=1000, min=1, max=100000,
        description="Most optimisation steps per island (more: less stretch on hard shapes, slower; L-BFGS "
                    "iterations)")
    margin: bpy.props.FloatProperty(
        name="Margin", default=0.02, min=0.0, max=0.5,
        description="Space between unpinned islands when they are packed into the unit square")
    pin_mode: bpy.props.EnumProperty(
        name="Pins", default="PLACE",
        items=(("PLACE", "Place and Turn", "Pinned UVs place and turn their island; its size follows the "
                "surface at the texel density of the layout it had (pins move a little if the surface "
                "disagrees with them)"),
               ("EXACT", "Exact", "Every pinned UV stays exactly where it is; the island stretches to meet "
                "them (hard constraints)")))

    @classmethod
    def poll(cls, context):
        return poll_reasons.one_mesh(cls, context, {"EDIT"})

    def prepare(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj):  # UV layers are in the BMesh in Edit Mode
            mesh = obj.data
            selected = np.zeros(len(mesh.polygons), dtype=bool)
            mesh.polygons.foreach_get("select", selected)
            if not selected.any():
                raise UserError("select the faces to unwrap")
            layer = mesh.uv_layers.active
            uv = uv_patch.read_uv(mesh, layer) if layer is not None else None
            pins = uv_patch.uv_pins(mesh, layer) if layer is not None else None
            # Read here: back in Edit Mode the layer is gone (5.x reads its name as "").
            layer_name = layer.name if layer is not None else "UVMap"
            islands = uv_patch.selected_islands(mesh, selected, uv, pins)
        _require_discs(islands)
        state = {"object": obj.name, "islands": islands, "faces": sum(len(island.F) for island in islands),
                 "layer": layer_name}
        options = {"max_iterations": self.max_iterations, "backend": backend(context),
                   "margin": self.margin}
        if self.pin_mode == "PLACE" and uv is not None:
            densities = []
            for island in islands:
                layout = np.zeros((len(island.V), 2))
                layout[island.loop_vertex] = uv[island.loops]
                densities.append(uv_patch.texel_density(island, layout) if len(island.pinned) >= 1 else None)
            # Pins on a degenerate layout: size the island from the others' density, else pins exact.
            known = [d for d in densities if d is not None]
            options["densities"] = [d if d is not None or not len(island.pinned) else
                                    (float(np.median(known)) if known else None)
                                    for d, island in zip(densities, islands)]
        return _map_islands, (islands,), options, state

    def describe_error(self, error, state):
        """Folds the pins force, in the operator's words (the native text
        speaks to scripts: "pass allow_folds=True")."""
        folded = re.match(r"(\d+) faces? stays? folded", str(error))
        if not isinstance(error, native.ConstraintError) or folded is None:
            return super().describe_error(error, state)
        count = int(folded.group(1))
        count = f"{count} face stays folded" if count == 1 else f"{count} faces stay folded"
        # Only exact pins are constraints; placed ones only place and turn their island.
        pins = sum(len(island.pinned) for island in state["islands"]) if self.pin_mode == "EXACT" else 0
        if pins:
            return (f"the pinned UVs cannot all be met without folds ({count}; is a pin mirrored or are two "
                    "swapped?): move or unpin some, or set Pins to Place and Turn")
        return f"the selection could not be flattened without folds ({count}): mark more seams"

    def finish(self, context, result, state):
        results, stats, offsets = result
        obj = bpy.data.objects[state["object"]]
        with bridge.object_mode(context, obj):
            mesh = obj.data
            layer = mesh.uv_layers.get(state["layer"]) or mesh.uv_layers.new(name=state["layer"])
            mesh.uv_layers.active = layer
            uv = uv_patch.read_uv(mesh, layer)
            for island, island_uv in zip(state["islands"], results):
                uv[island.loops] = island_uv[island.loop_vertex]
            bridge.write_uv_layer(mesh, uv, layer.name)
        pins = sum(len(island.pinned) for island in state["islands"])
        folds = sum(m.flipped for m in stats)
        moved = max(offsets) if offsets else 0.0
        kept = (f"{_count(pins, 'pinned UV')} placed the islands (moved {moved:.3g} at most)" if moved > 1e-9
                else f"{_count(pins, 'pinned UV')} kept")
        return (f"Isometric Unwrap: {_count(len(stats), 'island')}, {kept}, "
                f"{distortion_words(stats)}" + (f", {_count(folds, 'fold')}" if folds else ", no folds"))


def _menu_entry(self, context):
    self.layout.operator(PARAMORPH_OT_isometric_unwrap.bl_idname)


classes = (PARAMORPH_OT_isometric_unwrap,)


def register():
    bpy.types.VIEW3D_MT_uv_map.append(_menu_entry)
    bpy.types.IMAGE_MT_uvs.append(_menu_entry)


def unregister():
    bpy.types.VIEW3D_MT_uv_map.remove(_menu_entry)
    bpy.types.IMAGE_MT_uvs.remove(_menu_entry)
