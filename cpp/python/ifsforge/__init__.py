"""ifsforge: fractal content from iterated function systems, for Blender and POV-Ray.

The compiled core (`ifsforge._core`) holds the model, the file formats and the renderers;
this package re-exports it under the same names as the C++ API.
"""
from ifsforge._core import (  # noqa: F401
    FORMAT_VERSION,
    choices,  # the names of every enumerated setting, e.g. choices["density"] (one table in C++)
    AffineMap,
    BoxCounting,
    ChannelLayout,
    Ifs,
    MapParams,
    Raster,
    box_counting,
    contraction_factor_2d,
    default_depth,
    default_iterations,
    hsi_to_rgb,
    jacobian_probabilities,
    load,
    parse_fractint,
    parse_json,
    read_fractint,
    read_json,
    read_png,
    render,
    renderer_capabilities,
    renderers,
    sampler_capabilities,
    volume_renderer_capabilities,
    seed_reference,
    to_json,
    write_json,
    default_threads,
    check_memory,
    memory_budget,
    mesh_edges,
    set_default_threads,
    write_mesh,
    write_bytes,
    write_png,
)
from ifsforge._core import Up, default_up, linear_to_srgb, srgb_to_linear  # noqa: F401  (axes, colour rule)
from ifsforge._core import PreviewCloud, morph, pad_maps, piece_color, preview_cloud  # noqa: F401  (design)
from ifsforge._core import (  # noqa: F401  (terrain: fractal interpolation, terrains, palettes)
    FractalInterpolation, Palette, PaletteRecipe, PaletteSpec, Terrain, TerrainControls, TerrainControlsOptions,
    TerrainRecipe, make_terrain_controls, set_roughness, terrain_defaults,
    apply_palette, hls_to_rgb, make_palette, make_terrain, parse_palette_recipe, parse_terrain_recipe,
    pov_color_map, random_heights, random_shifts, read_palette_recipe, read_terrain_recipe,
    sample_heights, vertical_scaling, write_terrain_mesh, write_terrain_pov,
)
from ifsforge._core import BreedOptions, PolarMap, breed, polar_ifs  # noqa: F401  (polar IFS, 3.3.3)
from ifsforge._core import (  # noqa: F401  (algorithms: recurrent/super IFS, condensation, chapter-5 extras)
    Condensation, color_bounds, growth_frames, make_super_ifs, proximity_bound, renderer_parameters,
)
from ifsforge._core import (  # noqa: F401  (vector: instance lists, addresses, POV-Ray/SVG/glTF)
    AddressLeaves, AddressTable, InstanceList, Primitive, apply_address, count_leaves, default_instance_depth,
    ascii_text, draw_instances, instances, pov_comment, pov_identifier, pov_name, pov_reserved_words, pov_string,
    povray_include, primitive_names, read_mesh,
    render_povray, string_rewriting, tesseral_synecdoche, write_address_csv, write_gltf_instances, write_pov_scene,
    write_povray_include, write_svg,
)
from ifsforge._core import (  # noqa: F401  (volume: Table 2 renderers, OpenVDB, POV-Ray df3, iso-surfaces)
    Volume, render_volume, volume_renderers, write_df3,
)
from ifsforge._core import (  # noqa: F401  (pifs: fractal image compression, seed 3.3.2)
    PifsCode, pifs_encode, pifs_from_bytes, read_pifs, write_pifs,
)
from ifsforge._core import (  # noqa: F401  (inverse problem: collage theorem, fitting)
    CollageTarget, ColorFitOptions, Fit3dOptions, FitOptions, attractor_iou, attractor_iou_3d, collage_distance, collage_mask,
    color_foreground, fit, fit_3d, fit_color, foreground, has_color, hausdorff_distance, tops, tops_warp,
)
from ifsforge._core import (  # noqa: F401  (the settings structs: every default lives in C++, once)
    DrawOptions, GltfInstanceOptions, InstanceOptions, MeshWriteOptions, PifsDecodeOptions, PifsEncodeOptions,
    PovRenderOptions, PovSceneOptions, PreviewOptions, RenderOptions, SvgOptions, TerrainMeshOptions,
    TerrainPovOptions, ToneOptions, TopsOptions, VolumeOptions,
)
from ifsforge.errors import (  # noqa: F401
    Cancelled,
    DivergentSystemError,
    Error,
    FileError,
    InputError,
    MemoryBudgetError,
)

__version__ = "0.1.0"

# OpenVDB files and iso-surfaces live in their own extension, imported on first use: loading
# libopenvdb is slow, and every command that writes no .vdb would otherwise pay for it.
_VDB_NAMES = ("IsoSurfaceOptions", "VdbWriteOptions", "VoxelTargetOptions", "read_vdb_info", "read_voxel_target",
              "render_volume_to_vdb", "volume_to_mesh", "write_vdb")


# Old spellings, kept for one release: the API writes color and normalize, as glTF, Blender and
# OpenVDB do.
_DEPRECATED = {"fit_colour": "fit_color", "has_colour": "has_color", "colour_foreground": "color_foreground",
               "ColourFitOptions": "ColorFitOptions"}


def __getattr__(name):
    if name in _DEPRECATED:
        import warnings
        warnings.warn(f"ifsforge.{name} is deprecated; use ifsforge.{_DEPRECATED[name]}", DeprecationWarning, stacklevel=2)
        return globals()[_DEPRECATED[name]]
    if name in ("read_vdb_info", "read_voxel_target"):
        from ifsforge import vdb_reader  # a .vdb is read in a child process: see its docstring
        return getattr(vdb_reader, name)
    if name in _VDB_NAMES:
        from ifsforge import _vdb
        return getattr(_vdb, name)
    raise AttributeError(f"module 'ifsforge' has no attribute '{name}'")


def __dir__():
    return sorted(list(globals()) + list(_VDB_NAMES))
