import bpy
op = bpy.context.active_operator

op.sample = 'barnsley_fern.json'
op.settings.terrain_source = 'RANDOM'
op.settings.terrain_resolution = 1025
