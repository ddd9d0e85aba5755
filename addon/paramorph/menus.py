"""One "Paramorph" submenu in the 3D View's Object menu and one in Edit
Mode's Mesh menu (issue 20), so the add-on's entries sit together instead of
loose under Delete, and F3's menu search finds every one of them by
"Paramorph" (it matches the menu path "Object > Paramorph > Sphere Map")."""
import bpy


class PARAMORPH_MT_object(bpy.types.Menu):
    bl_idname = "PARAMORPH_MT_object"
    bl_label = "Paramorph"

    def draw(self, context):
        layout = self.layout
        layout.operator("paramorph.sphere_map")
        layout.operator("paramorph.segment_extremities")
        layout.operator("paramorph.detect_feature_regions")
        layout.operator("paramorph.rank_similar_shapes")
        layout.separator()
        layout.operator("paramorph.pick_pins")
        layout.operator("paramorph.preview_matches")
        layout.operator("paramorph.morph_to")
        layout.separator()
        layout.operator("paramorph.paste_feature")


class PARAMORPH_MT_edit_mesh(bpy.types.Menu):
    bl_idname = "PARAMORPH_MT_edit_mesh"
    bl_label = "Paramorph"

    def draw(self, context):
        layout = self.layout
        layout.operator("paramorph.copy_feature")
        layout.operator("paramorph.paste_feature")
        layout.separator()
        layout.operator("paramorph.isometric_unwrap")
        layout.operator("paramorph.sphere_map")


def _object_menu(self, context):
    self.layout.separator()
    self.layout.menu(PARAMORPH_MT_object.bl_idname)


def _edit_mesh_menu(self, context):
    self.layout.separator()
    self.layout.menu(PARAMORPH_MT_edit_mesh.bl_idname)


classes = (PARAMORPH_MT_object, PARAMORPH_MT_edit_mesh)


def register():
    bpy.types.VIEW3D_MT_object.append(_object_menu)
    bpy.types.VIEW3D_MT_edit_mesh.append(_edit_mesh_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_object_menu)
    bpy.types.VIEW3D_MT_edit_mesh.remove(_edit_mesh_menu)
