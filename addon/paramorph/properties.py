"""Scene settings the sidebar panel edits; operators read their defaults from
here, and their own properties (the redo panel) override them. Everything
here is saved with the .blend (the morph's pins included)."""
import bpy


class ParamorphSettings(bpy.types.PropertyGroup):
    show_overlay: bpy.props.BoolProperty(
        name="Show Regions", default=True,
        description="Draw the active mesh's regions, borders and feature points, and the morph's "
                    "pins and pairs, in the viewport")
    region_index: bpy.props.IntProperty(
        name="Region", default=0, min=0, description="Region to select by index")
    similar_reference: bpy.props.StringProperty(
        name="Reference", description="The object the similar-shapes list was ranked against")


class ParamorphMatchPair(bpy.types.PropertyGroup):
    """A vertex of the source that the morph takes exactly onto a vertex of the
    target. Pins are the user's (always used); the others are the automatic
    pairs Preview Matches found (used by Morph To with Use Previewed Pairs)."""
    vertex_a: bpy.props.IntProperty(name="Source Vertex", min=0,
                                    description="Vertex of the source (its index in the mesh)")
    vertex_b: bpy.props.IntProperty(name="Target Vertex", min=0,
                                    description="Vertex of the target it lands on at the end of the morph")
    pin: bpy.props.BoolProperty(name="Pin", description="Given by the user: always used")
    kind: bpy.props.StringProperty(
        name="Kind", description="The automatic candidate the pair came from (extremities, tip paths, "
                                 "registration, features; empty for a pin)")


class ParamorphCandidate(bpy.types.PropertyGroup):
    """One automatic correspondence Preview Matches weighed, and its score."""
    kind: bpy.props.StringProperty(
        name="Kind", description="none, extremities, tip paths, pin distances, registration, features or given")
    detail: bpy.props.StringProperty(name="Detail", description="What the candidate pairs")
    score: bpy.props.FloatProperty(
        name="Score", description="Distortion of the correspondence it makes plus the curvature mismatch "
                                  "(lower is better; infinite when rejected)")
    distortion: bpy.props.FloatProperty(name="Distortion", description="Mean isometric distortion (0: isometric)")
    rejected: bpy.props.StringProperty(name="Rejected", description="Why it was not scored (empty when scored)")
    chosen: bpy.props.BoolProperty(name="Chosen", description="The candidate the morph uses")
    pairs: bpy.props.IntProperty(name="Pairs", description="Its automatic pairs (on the proxies)")


class ParamorphMatches(bpy.types.PropertyGroup):
    """The pins the user picked and the pairs and candidates "Preview Matches"
    found for a source and a target, used by "Morph To" on the same two
    objects."""
    source: bpy.props.PointerProperty(type=bpy.types.Object, name="Source")
    target: bpy.props.PointerProperty(type=bpy.types.Object, name="Target")
    # Vertex counts when the pins were picked: indices for other geometry are stale.
    source_vertices: bpy.props.IntProperty(options={"HIDDEN"})
    target_vertices: bpy.props.IntProperty(options={"HIDDEN"})
    pairs: bpy.props.CollectionProperty(type=ParamorphMatchPair)
    pair_index: bpy.props.IntProperty(name="Pair", default=0, min=0)
    candidates: bpy.props.CollectionProperty(type=ParamorphCandidate)
    show_candidates: bpy.props.BoolProperty(
        name="Show Candidates", default=False,
        description="List every automatic candidate Preview Matches weighed, with its score")


def register():
    bpy.utils.register_class(ParamorphSettings)
    bpy.utils.register_class(ParamorphMatchPair)
    bpy.utils.register_class(ParamorphCandidate)
    bpy.utils.register_class(ParamorphMatches)
    bpy.types.Scene.paramorph = bpy.props.PointerProperty(type=ParamorphSettings)
    bpy.types.Scene.paramorph_matches = bpy.props.PointerProperty(type=ParamorphMatches)
    # Readable in Edit Mode too, where the face attribute is not.
    bpy.types.Object.paramorph_regions = bpy.props.IntProperty(
        name="Regions", default=0, min=0, options={"HIDDEN"},
        description="Regions in the paramorph_region face attribute (0: not segmented)")


def unregister():
    del bpy.types.Object.paramorph_regions
    del bpy.types.Scene.paramorph_matches
    del bpy.types.Scene.paramorph
    bpy.utils.unregister_class(ParamorphMatches)
    bpy.utils.unregister_class(ParamorphCandidate)
    bpy.utils.unregister_class(ParamorphMatchPair)
    bpy.utils.unregister_class(ParamorphSettings)
