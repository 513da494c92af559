"""The recogniser's search levels by ground resolution, as core/detect/search_levels.cc chooses them (the
training side composes its windows at the same levels). Pure Python, no torch: tests/core/detect/
search_levels_python_test.cc runs it beside the C++ rule on the same inputs."""
import math

EARTH_CIRCUMFERENCE_M = 40075016.685578488  # 2 pi 6378137, core/geo/web_mercator.h


def zoom_fitting_size(size_m, lat_deg, tile=256):
    """The zoom whose tile side (metres) is nearest, by ratio, to size_m (ZoomFittingSize)."""
    side0_m = EARTH_CIRCUMFERENCE_M * math.cos(math.radians(lat_deg))  # a zoom-0 tile's side
    v = math.log2(side0_m / size_m)
    return int(math.floor(v + 0.5)) if v >= 0 else -int(math.floor(-v + 0.5))  # std::lround: halves away from 0


def scale_matched_zooms(class_sizes_m, base_zoom, min_zoom, lat_deg, tile=256):
    """Finest first, from the zoom fitting the smallest class size to the one fitting the largest, 2 zooms
    apart; levels above base_zoom + 1 or below min_zoom left out (ScaleMatchedZooms). class_sizes_m: a size
    per class (a [min, max] pair counts as its max), 0 = unknown."""
    sizes = [max(s) if isinstance(s, (list, tuple)) else s for s in class_sizes_m]
    sizes = [s for s in sizes if s > 0]
    if not sizes:
        return []
    coarse = zoom_fitting_size(max(sizes), lat_deg, tile)
    fine = max(coarse, zoom_fitting_size(min(sizes), lat_deg, tile))
    out = []
    z = coarse + 2 * ((fine - coarse + 1) // 2)
    while z >= coarse:
        if min_zoom <= z <= base_zoom + 1:
            out.append(z)
        z -= 2
    return out


def overzoomed_tiles(tiles, base_zoom, tile=256):
    """{(base_zoom + 1, x, y): the quarter of its parent scaled up 2x (bilinear)} for every stored tile of
    base_zoom in `tiles` ({(z, x, y): image}), as OverzoomedTile composes them."""
    import cv2
    half = tile // 2
    out = {}
    for (z, x, y), img in tiles.items():
        if z != base_zoom or img.shape[0] != tile or img.shape[1] != tile:
            continue
        for dy in range(2):
            for dx in range(2):
                q = img[dy * half:(dy + 1) * half, dx * half:(dx + 1) * half]
                out[(z + 1, 2 * x + dx, 2 * y + dy)] = cv2.resize(q, (tile, tile), interpolation=cv2.INTER_LINEAR)
    return out


if __name__ == "__main__":  # lines "lat base min size..." in, "z z ..." out (for the C++ comparison test)
    import sys
    for line in sys.stdin:
        f = line.split()
        if f:
            lat, base, zmin, sizes = float(f[0]), int(f[1]), int(f[2]), [float(v) for v in f[3:]]
            print(" ".join(map(str, scale_matched_zooms(sizes, base, zmin, lat))))
