import bpy
op = bpy.context.active_operator

op.sample = 'vector_csg_pyramid.json'
op.settings.instance_depth = 0
