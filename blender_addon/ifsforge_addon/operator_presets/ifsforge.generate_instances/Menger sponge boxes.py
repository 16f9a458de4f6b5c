import bpy
op = bpy.context.active_operator

op.sample = 'menger_sponge.json'
op.settings.instance_depth = 3
op.settings.instance_primitives = 'box'
