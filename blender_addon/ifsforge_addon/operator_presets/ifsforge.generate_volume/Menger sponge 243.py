import bpy
op = bpy.context.active_operator

op.sample = 'menger_sponge.json'
op.settings.volume_resolution = 243
