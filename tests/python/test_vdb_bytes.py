"""The `.vdb` writer's bytes are pinned: for fixed inputs (a sample, a resolution, the density and
the write options) the file hashes to the digest the reference writer produced, whether the volume
is written whole (write_vdb) or band by band from the render (render_volume_to_vdb), and on one
thread or two. A faster writer must write every byte the same."""
import hashlib

import pytest

import ifsforge

# (sample, resolution, render keywords, write keywords, voxels, file bytes, SHA-256). Resolutions
# cross the 8-voxel leaves and the 128-row bands unevenly; the samples cover RGB, HSI, gray,
# alpha and 6D colour, binary and hit-count densities, halves and Blosc. The digests are those of
# unfused arithmetic (-ffp-contract=off, every build): a build that fused multiply-adds wrote other
# bytes for the coral and the fern, whose maps rotate.
CASES = [
    ("volume_sierpinski_pyramid_rgb", 40, {}, {}, 7828, 99117,
     "138a0877a4a290892255a027119e0413b0041a5ff969fef72308c8abc5a2d1fd"),
    ("volume_sierpinski_pyramid_rgb", 200, {"density": "hits"}, {}, 355440, 4275943,
     "9e2275d140ce38d87f1c98986a4fb7b6a5551c1aec2c5eb0a2c80704f3d31453"),
    ("volume_sierpinski_pyramid_rgb", 200, {}, {"half": True}, 355440, 3565075,
     "cd3a9c3a0fc8a78d51e48a4751b978fc11c8d258c5017bb184d8d41d01a7df8f"),
    ("volume_sierpinski_pyramid_rgb", 200, {}, {"compress": True}, 355440, 2584656,
     "3e5e37bf49f72148d887d0a1dfc06c45da476a731a7bcf9911e66c32b5bc3d03"),
    ("volume_hsi_tower", 129, {"density": "hits"}, {}, None, None,
     "003a1eaeb67e488f55b7c380995a9e0f3588d04bed681b9f191fea20660c5f44"),
    ("volume_menger_gray", 81, {}, {}, 160000, 2093331,
     "e6042227eefa746280e0fc7780405faa9bc05c86a76e7ca4dcd4bdabb2d45445"),
    ("volume_menger_gray", 81, {}, {"half": True, "compress": True}, 160000, 1815900,
     "407fb18d8d60ae5753ed1d9fb42e654ca0a51c1fb900c5ffc6addaed93bdda5c"),
    ("volume_tetrahedron_alpha", 257, {"density": "hits"}, {"color_scale": "range"}, 130708, 1349150,
     "f10db97fa777763ac6a6572d86bfeb7a26234d16e04a0f608c60fb142229c4c6"),
    ("volume_coral_6d", 96, {}, {}, 58425, 581468,
     "fb0ac9e7cd7fec14349623b5e6aaa1469505fa708a474b065622d9df90cdb2a3"),
    ("volume_fern_3d", 300, {}, {}, 25632, 156984,
     "2c747561345fc852c2b0d339f0f9e04a90c31b384e9dfe2173f879f5d088c03c"),
]


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("sample, resolution, render, write, voxels, size, expected", CASES,
                         ids=[f"{c[0]}-{c[1]}-{i}" for i, c in enumerate(CASES)])
def test_vdb_bytes_equal_the_reference_writers(tmp_path, samples, sample, resolution, render, write, voxels, size,
                                               expected):
    ifs = ifsforge.load(str(samples / f"{sample}.json"))
    volume = ifsforge.render_volume(ifs, "prr", resolution, **render)
    if voxels is not None:
        assert len(volume) == voxels
    for threads in (1, 2):
        whole = tmp_path / f"whole{threads}.vdb"
        ifsforge.write_vdb(str(whole), volume, system=ifs, threads=threads, **write)
        assert size is None or whole.stat().st_size == size
        assert digest(whole) == expected, f"write_vdb on {threads} thread(s)"
    banded = tmp_path / "banded.vdb"
    ifsforge.render_volume_to_vdb(str(banded), ifs, "prr", resolution=resolution, **render, **write)
    assert digest(banded) == expected, "render_volume_to_vdb"
