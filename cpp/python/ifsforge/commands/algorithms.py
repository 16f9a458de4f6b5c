"""ifsforge algorithms: the rendering algorithms available to `render`."""
import ifsforge


def register(subparsers):
    p = subparsers.add_parser("algorithms", help="list the rendering algorithms")
    p.set_defaults(run=run)


def run(args):
    for name, description in ifsforge.renderers():
        print(f"{name:18s} {description}")
        for key, default, text in ifsforge.renderer_parameters(name):
            print(f"{'':20s}--param {key}={default or '(auto)'}: {text}")
    return 0
