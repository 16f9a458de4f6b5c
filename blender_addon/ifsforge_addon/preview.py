"""The live viewport preview: the attractor as points (ifsforge.preview_cloud) drawn with the
gpu module, and the collage frames. The cloud is rebuilt when a value of the edited system
changes (seen by comparing values at draw time, so dragging, keyframes and undo all update
it); drawing itself needs a display, the data path does not."""
import time

import bpy

import ifsforge

from . import collage, generators, state

_handle = None
# Generated objects in the system's own coordinates: the preview follows their transform.
SYSTEM_SPACE = {'VOLUME', 'INSTANCES', 'MESH'}


class Preview:
    """The last cloud computed, with the key it was computed for."""

    def __init__(self):
        self.key = None
        self.cloud = None
        self.error = ""
        self.seconds = 0.0         # computing the last cloud
        self.upload_seconds = 0.0  # turning it into GPU batches
        self.batches = None

    def update(self, context):
        """Recompute the cloud if the edited system or the preview settings changed. Returns
        the cloud (None when the system cannot be previewed; `error` says why)."""
        owner, pg, _ = state.target(context)
        settings = context.scene.ifsforge.preview
        analysis = state.analyse(pg)
        highlight = pg.active_map if settings.highlight_active and not pg.morph.enabled else -1
        key = (owner.as_pointer(), analysis.serial, settings.count, settings.coloring, highlight)
        if key == self.key:
            return self.cloud
        start = time.perf_counter()
        self.key, self.cloud, self.batches, self.error = key, None, None, analysis.error
        if analysis.usable:
            try:
                self.cloud = ifsforge.preview_cloud(analysis.system, settings.count, seed=0, coloring=settings.coloring,
                                                    highlight=highlight)
            except ifsforge.Error as error:
                self.error = str(error)
        self.seconds = time.perf_counter() - start
        return self.cloud


current = Preview()


def _batches(cloud):
    import gpu
    from gpu_extras.batch import batch_for_shader
    shader = gpu.shader.from_builtin('FLAT_COLOR')
    points = batch_for_shader(shader, 'POINTS', {"pos": cloud.positions, "color": cloud.colors})
    frames = batch_for_shader(shader, 'LINES', {"pos": cloud.frame_positions, "color": cloud.frame_colors})
    return shader, points, frames


def _draw_target(context, system):
    """The target picture on its window, just below the plane, and each map's copy of the window."""
    import gpu
    from gpu_extras.batch import batch_for_shader
    settings = context.scene.ifsforge.collage
    if not settings.show or settings.image is None or system is None or system.spatial_dims != 2:
        return
    xmin, ymin, xmax, ymax = settings.window
    texture = gpu.texture.from_image(settings.image)
    shader = _image_shader()
    quad = batch_for_shader(shader, 'TRI_FAN', {
        "pos": [(xmin, ymin, -1e-4), (xmax, ymin, -1e-4), (xmax, ymax, -1e-4), (xmin, ymax, -1e-4)],
        "texCoord": [(0, 0), (1, 0), (1, 1), (0, 1)]})
    shader.bind()
    shader.uniform_sampler("image", texture)
    quad.draw(shader)
    lines, colors = [], []
    for i, corners in enumerate(collage.outlines(system, settings.window)):
        color = tuple(ifsforge.piece_color(i))
        for k in range(4):
            lines += [corners[k], corners[(k + 1) % 4]]
            colors += [color, color]
    flat = gpu.shader.from_builtin('FLAT_COLOR')
    batch_for_shader(flat, 'LINES', {"pos": lines, "color": colors}).draw(flat)


def _image_shader():
    """The built-in textured shader taking 3D positions: 'IMAGE' (Blender 3.4 on), else '3D_IMAGE'."""
    import gpu
    try:
        return gpu.shader.from_builtin('IMAGE')
    except ValueError:
        return gpu.shader.from_builtin('3D_IMAGE')


def draw():
    """SpaceView3D draw handler (POST_VIEW)."""
    context = bpy.context
    scene = context.scene
    if scene is None or not hasattr(scene, "ifsforge") or not scene.ifsforge.preview.show:
        return
    try:
        cloud = current.update(context)
    except ifsforge.Error:
        return
    if cloud is None:
        return
    import gpu
    if current.batches is None:
        start = time.perf_counter()
        current.batches = _batches(cloud)
        current.upload_seconds = time.perf_counter() - start
    shader, points, frames = current.batches
    owner, _, _ = state.target(context)
    settings = scene.ifsforge.preview
    gpu.matrix.push()
    if isinstance(owner, bpy.types.Object) and owner.ifsforge.kind in SYSTEM_SPACE:
        gpu.matrix.multiply_matrix(generators.system_matrix(owner))
    gpu.state.depth_test_set('LESS_EQUAL')
    gpu.state.blend_set('ALPHA')
    gpu.state.point_size_set(settings.point_size)
    _draw_target(context, state.analyse(state.target(context)[1]).system)
    shader.bind()
    points.draw(shader)
    if settings.show_frames:
        gpu.state.line_width_set(1.5)
        frames.draw(shader)
        gpu.state.line_width_set(1.0)
    gpu.state.point_size_set(1.0)
    gpu.state.blend_set('NONE')
    gpu.state.depth_test_set('NONE')
    gpu.matrix.pop()


def register():
    global _handle
    _handle = bpy.types.SpaceView3D.draw_handler_add(draw, (), 'WINDOW', 'POST_VIEW')


def unregister():
    global _handle
    if _handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handle, 'WINDOW')
        _handle = None
    current.__init__()
