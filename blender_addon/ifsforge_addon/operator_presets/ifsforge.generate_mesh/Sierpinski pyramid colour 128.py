import bpy
op = bpy.context.active_operator

op.sample = 'volume_sierpinski_pyramid_rgb.json'
op.settings.volume_resolution = 128
