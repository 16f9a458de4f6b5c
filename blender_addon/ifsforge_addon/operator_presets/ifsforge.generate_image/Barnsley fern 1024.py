import bpy
op = bpy.context.active_operator

op.sample = 'barnsley_fern.json'
op.settings.image_size = 1024
