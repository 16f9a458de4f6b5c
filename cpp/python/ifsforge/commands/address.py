"""ifsforge address: the address(es) of the attractor point nearest to a point (seed 3.3.1)."""

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("address", help="addresses of the attractor point nearest to a point (3.3.1)")
    common.add_system_argument(p)
    p.add_argument("coordinates", nargs="+", type=common.NUMBER, metavar="X", help="X Y (2D) or X Y Z (3D)")
    p.add_argument("--depth", type=common.count_option(64), default=8, help="address length (default 8)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(run=run)


def run(args):
    system = common.load_system(args.system)
    addresses, distance = system.address_of(args.coordinates, args.depth)
    if args.json:
        print(common.to_json({"addresses": addresses, "distance": distance}, indent=None))
        return 0
    for address in addresses:
        print(".".join(map(str, address)))
    print(f"nearest attractor point found at distance {distance:.6g}")
    return 0
