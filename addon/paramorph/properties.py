"""Scene settings the sidebar panel edits; operators read their defaults from
here, and their own properties (the redo panel) override them."""
import bpy


class ParamorphSettings(bpy.types.PropertyGroup):
    show_overlay: bpy.props.BoolProperty(
        name="Show Regions", default=True,
        description="Draw the active mesh's regions, borders and feature points in the viewport")
    region_index: bpy.props.IntProperty(
        name="Region", default=0, min=0, description="Region to select by index")
    similar_reference: bpy.props.StringProperty(
        name="Reference", description="The object the similar-shapes list was ranked against")


class ParamorphMatchPair(bpy.types.PropertyGroup):
    """A feature-point pair of the match preview: a vertex of the source and
    one of the target. Pins are the user's; the others came from matching."""
    vertex_a: bpy.props.IntProperty(name="Source Vertex", min=0)
    vertex_b: bpy.props.IntProperty(name="Target Vertex", min=0)
    score: bpy.props.FloatProperty(name="Score", description="Distance after alignment (lower is better)")
    pin: bpy.props.BoolProperty(name="Pin", description="Given by the user: always used")


class ParamorphMatches(bpy.types.PropertyGroup):
    """The pairs "Preview Matches" found for a source and a target, edited by
    the user, and used by "Morph To" on the same two objects."""
    source: bpy.props.PointerProperty(type=bpy.types.Object, name="Source")
    target: bpy.props.PointerProperty(type=bpy.types.Object, name="Target")
    # Vertex counts at preview time: a pair list for other geometry is stale.
    source_vertices: bpy.props.IntProperty(options={"HIDDEN"})
    target_vertices: bpy.props.IntProperty(options={"HIDDEN"})
    pairs: bpy.props.CollectionProperty(type=ParamorphMatchPair)
    pair_index: bpy.props.IntProperty(name="Pair", default=0, min=0)


def register():
    bpy.utils.register_class(ParamorphSettings)
    bpy.utils.register_class(ParamorphMatchPair)
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
    bpy.utils.unregister_class(ParamorphMatchPair)
    bpy.utils.unregister_class(ParamorphSettings)
