import bpy
op = bpy.context.active_operator

op.sample = 'barnsley_fern.json'
op.settings.terrain_source = 'ATTRACTOR'
op.settings.terrain_resolution = 513
