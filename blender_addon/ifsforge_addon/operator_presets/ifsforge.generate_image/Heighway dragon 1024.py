import bpy
op = bpy.context.active_operator

op.sample = 'heighway_dragon.json'
op.settings.image_size = 1024
