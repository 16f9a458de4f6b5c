"""ifsforge: fractal content from iterated function systems, for Blender and POV-Ray.

The compiled core (`ifsforge._core`) holds the model, the file formats and the renderers;
this package re-exports it under the same names as the C++ API.
"""
from ifsforge._core import (  # noqa: F401
    FORMAT_VERSION,
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
    renderers,
    to_json,
    write_json,
    write_mesh,
    write_png,
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
