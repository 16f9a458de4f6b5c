import bpy
op = bpy.context.active_operator

op.sample = 'vector_sphere_tree.json'
op.settings.instance_depth = 0
