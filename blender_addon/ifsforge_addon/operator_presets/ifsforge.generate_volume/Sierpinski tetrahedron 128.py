import bpy
op = bpy.context.active_operator

op.sample = 'sierpinski_tetrahedron.json'
op.settings.volume_resolution = 128
