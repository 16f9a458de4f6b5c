import bpy
op = bpy.context.active_operator

op.sample = 'volume_coral_6d.json'
op.settings.volume_resolution = 128
op.settings.volume_density = 'hits'
