"""ifsforge algorithms: the rendering algorithms, the systems each handles and its settings."""
import ifsforge


def register(subparsers):
    p = subparsers.add_parser("algorithms", help="list the rendering algorithms and the systems each handles")
    p.set_defaults(run=run)


def handles(capabilities):
    """'handles: 2D, 3D, recurrent, ...' from a renderer's declared capabilities (the core's table:
    dispatch refuses a system a renderer does not declare, naming those that do)."""
    words = {"2d": "2D", "3d": "3D", "recurrent": "recurrent", "polar": "polar",
             "average_contractive": "average-contractive", "overlapping": "overlapping",
             "condensation": "condensation sets"}
    return "handles: " + ", ".join(text for key, text in words.items() if capabilities.get(key))


def run(args):
    images = ifsforge.renderer_capabilities()
    for name, description in ifsforge.renderers():
        print(f"{name:18s} {description}")
        print(f"{'':20s}{handles(images[name])}")
        for key, default, text in ifsforge.renderer_parameters(name):
            print(f"{'':20s}--param {key}={default or '(auto)'}: {text}")
    print("\nvolume renderers (ifsforge volume -a NAME):")
    for name, capabilities in ifsforge.volume_renderer_capabilities().items():
        print(f"{name:18s} {handles(capabilities)}")
    print("\nsamplers (framing, previews, fits):")
    for name, capabilities in ifsforge.sampler_capabilities().items():
        print(f"{name:18s} {handles(capabilities)}")
    return 0
