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


def register():
    bpy.utils.register_class(ParamorphSettings)
    bpy.types.Scene.paramorph = bpy.props.PointerProperty(type=ParamorphSettings)
    # Readable in Edit Mode too, where the face attribute is not.
    bpy.types.Object.paramorph_regions = bpy.props.IntProperty(
        name="Regions", default=0, min=0, options={"HIDDEN"},
        description="Regions in the paramorph_region face attribute (0: not segmented)")


def unregister():
    del bpy.types.Object.paramorph_regions
    del bpy.types.Scene.paramorph
    bpy.utils.unregister_class(ParamorphSettings)
