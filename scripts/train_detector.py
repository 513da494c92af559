#!/usr/bin/python3
"""Trains the seabed object detector that SeaMap ships (data/models/seabed_objects.onnx).

Run with Debian's own Python (python3-torch, python3-torchvision, python3-onnx, python3-opencv):
  scripts/train_detector.py --seamap build/seamap --work /tmp/seamap_train [--minutes 30]
or train elsewhere (a GPU machine with torch, torchvision and cv2 but no SeaMap build) from a pack of windows:
  scripts/train_detector.py --pack windows.npz                    # here: simulate, build, compose, pack
  python3 train_detector.py --from-pack windows.npz --device cuda --workers 14 --batch 64 --crop 256 \
      --lr 3e-3 --minutes 7 --no-export --work OUT                # there: writes OUT/ema.npz
  scripts/train_detector.py --from-pack windows.npz --minutes 0 --resume OUT/ema.npz   # here: export, check
Simulates surveys with objects (training seeds 1000+, validation 2000+), builds them into MBTiles, composes the
detector's windows from the tiles, trains on random crops, exports ONNX (opset 12, YOLOv8 layout decoded in
4-D), checks it with cv2.dnn and validates with the 10 cm rule. See docs/DETECTION_MODEL.md.
"""
import argparse
import hashlib
import json
import math
import os
import random
import re
import sqlite3
import subprocess
import sys
import time

# Idle OpenMP threads sleep instead of spinning: on a loaded machine a starved thread's partner spun for it, so a
# fine-tune step cost 0.94 CPU-s instead of 0.15 and a CPU-minute budget bought a sixth of the steps (before torch).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
import cv2
import numpy as np
import torch
import torch.nn as nn
import torchvision

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from search_levels import overzoomed_tiles, scale_matched_zooms  # noqa: E402  (the C++ level rule)
from detector_net import STRIDES, Detector, loss_fn  # noqa: E402  (the network and its loss)

CLASSES = ["tyre", "crate", "pipe", "anchor", "rock"]
CLASS_SIZES_M = {"tyre": [0.5, 1.0], "crate": [0.4, 1.2], "pipe": [1.5, 3.0], "anchor": [0.5, 1.5], "rock": [0.2, 0.8]}
TILE = 256
N_TILES = 3  # window of 3 x 3 tiles, starting at multiples of 2
GREY = 114


# ---------------------------------------------------------------- data

def run(cmd):
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def make_survey(seamap, work, seed, color, degrade, frames, objects, tile_format, clutter=0, extra=(), tag=""):
    """`extra`: more `seamap simulate` options (the robust surveys' conditions), `tag` names their cache folder."""
    d = os.path.join(work, f"survey_{seed}" + (f"_clutter{clutter}" if clutter else "") + (f"_{tag}" if tag else ""))
    mb = os.path.join(d, "map.mbtiles")
    if os.path.exists(mb) and os.path.exists(os.path.join(d, "truth", "objects.json")):
        return d
    cmd = [seamap, "simulate", "--out", d, "--force", "--quiet", "--seed", str(seed), "--frames", str(frames)]
    if color:
        cmd.append("--color")
    if degrade:
        cmd.append("--degrade")
    if clutter:
        cmd += ["--clutter", str(clutter)]
    cmd += list(extra)
    for k, n in enumerate((objects, objects * 3 // 4, objects // 2)):
        try:
            run(cmd + ["--objects", str(n)])
            break
        except subprocess.CalledProcessError:  # that many do not fit 1 m apart on this seed's path
            if k == 2:
                raise
    origin = json.load(open(os.path.join(d, "survey.json")))["origin"]
    run([seamap, "build", "--images", os.path.join(d, "photo"), "--nav", os.path.join(d, "nav.csv"), "--camera",
         os.path.join(d, "camera.json"), "--origin", f"{origin[0]},{origin[1]}", "--out", mb, "--overwrite",
         "--quiet", "--tile-format", tile_format])
    return d


def read_tiles(mbtiles):
    """{(z, x, y): BGRA uint8 256x256} with XYZ rows (the table stores TMS rows)."""
    con = sqlite3.connect(f"file:{mbtiles}?mode=ro", uri=True)
    tiles = {}
    for z, x, row, data in con.execute("SELECT zoom_level, tile_column, tile_row, tile_data FROM tiles"):
        img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
        if img is None:
            continue
        y = (1 << z) - 1 - row
        if img.ndim == 2:
            img = cv2.cvtColor(img, cv2.COLOR_GRAY2BGRA)
        elif img.shape[2] == 2:  # gray + alpha
            g, a = img[:, :, 0], img[:, :, 1]
            img = np.dstack([g, g, g, a])
        elif img.shape[2] == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGR2BGRA)
        tiles[(z, x, y)] = img
    con.close()
    return tiles


def compose_window(tiles, z, wx, wy, size):
    """The detector's window: n x n tiles, alpha-blended on grey, resized to size, RGB uint8."""
    n = N_TILES
    canvas = np.full((n * TILE, n * TILE, 3), GREY, np.float32)
    painted = 0
    for j in range(n):
        for i in range(n):
            t = tiles.get((z, wx + i, wy + j))
            if t is None:
                continue
            a = t[:, :, 3:4].astype(np.float32) / 255
            painted += int((t[:, :, 3] > 0).sum())
            region = canvas[j * TILE:(j + 1) * TILE, i * TILE:(i + 1) * TILE]
            region[:] = t[:, :, :3].astype(np.float32) * a + region * (1 - a)
    canvas = np.clip(np.round(canvas), 0, 255).astype(np.uint8)
    img = cv2.resize(canvas, (size, size), interpolation=cv2.INTER_AREA)
    return cv2.cvtColor(img, cv2.COLOR_BGR2RGB), painted / float((n * TILE) ** 2)


def lonlat_to_pixel(lon, lat, z):
    world = TILE * (1 << z)
    x = (lon + 180.0) / 360.0 * world
    y = (1 - math.asinh(math.tan(math.radians(lat))) / math.pi) / 2 * world
    return x, y


def pixel_to_lonlat(x, y, z):
    world = TILE * (1 << z)
    lon = 360.0 * x / world - 180.0
    lat = math.degrees(math.atan(math.sinh(math.pi * (1 - 2 * y / world))))
    return lon, lat


def detection_zooms(tiles, lat, class_sizes_m=None):
    """The levels `seamap detect` searches on this map (core/detect/search_levels: where the classes have their
    trained sizes, whatever the altitude); a level one above the base is added to `tiles`, scaled up."""
    zs = sorted({k[0] for k in tiles})
    base, zmin = zs[-1], zs[0]
    sizes = list((class_sizes_m or CLASS_SIZES_M).values())
    zooms = scale_matched_zooms(sizes, base, zmin, lat, TILE)
    if base + 1 in zooms:
        tiles.update(overzoomed_tiles(tiles, base, TILE))
    return zooms


def survey_windows(survey_dir, size, mbtiles=None):
    """Every window with painted pixels at the detection zooms: list of (image, boxes, meta)."""
    truth = json.load(open(os.path.join(survey_dir, "truth", "objects.json")))
    tiles = read_tiles(mbtiles or os.path.join(survey_dir, "map.mbtiles"))
    lat0 = truth["origin"][0]
    out = []
    r = size / float(N_TILES * TILE)
    for z in detection_zooms(tiles, lat0):
        xs = [k[1] for k in tiles if k[0] == z]
        ys = [k[2] for k in tiles if k[0] == z]
        boxes_px = []
        for o in truth["objects"]:
            pts = [lonlat_to_pixel(lon, lat, z) for lon, lat in o["footprint_lonlat"]]
            px = [p[0] for p in pts]
            py = [p[1] for p in pts]
            boxes_px.append((o["class_id"], min(px), min(py), max(px), max(py)))
        for wx in range(min(xs) // 2 * 2 - 2, max(xs) + 1, 2):
            for wy in range(min(ys) // 2 * 2 - 2, max(ys) + 1, 2):
                img, painted = compose_window(tiles, z, wx, wy, size)
                if painted < 0.02:
                    continue
                x0, y0 = wx * TILE, wy * TILE
                boxes = []
                for c, bx0, by0, bx1, by1 in boxes_px:
                    cx0, cy0 = max(bx0, x0), max(by0, y0)
                    cx1, cy1 = min(bx1, x0 + N_TILES * TILE), min(by1, y0 + N_TILES * TILE)
                    if cx1 <= cx0 or cy1 <= cy0:
                        continue
                    visible = (cx1 - cx0) * (cy1 - cy0) / ((bx1 - bx0) * (by1 - by0))
                    if visible < 0.4:
                        continue
                    boxes.append([c, (cx0 - x0) * r, (cy0 - y0) * r, (cx1 - x0) * r, (cy1 - y0) * r])
                out.append((img, np.array(boxes, np.float32).reshape(-1, 5), (z, wx, wy)))
    return out, truth


# ---------------------------------------------------------------- augmentation and batches

def augment(img, boxes, rng, photometric=1.0):
    """Flips, 90-degree turns, photometric changes, blur, noise (labels follow the geometry). `photometric` scales
    the brightness/contrast jitter and the haze (1: as the shipped training; less keeps an object's albedo
    against its seabed, the cue that tells a dark look-alike from a rock)."""
    h, w = img.shape[:2]
    b = boxes.copy()
    if rng.random() < 0.5:
        img = img[:, ::-1]
        b[:, [1, 3]] = w - b[:, [3, 1]]
    if rng.random() < 0.5:
        img = img[::-1]
        b[:, [2, 4]] = h - b[:, [4, 2]]
    if rng.random() < 0.5:  # transpose (with the flips: all eight 90-degree symmetries)
        img = img.transpose(1, 0, 2)
        b = b[:, [0, 2, 1, 4, 3]]
    img = np.ascontiguousarray(img).astype(np.float32)
    if rng.random() < 0.8:
        img = img * rng.uniform(1 - 0.4 * photometric, 1 + 0.4 * photometric) + \
            rng.uniform(-30 * photometric, 30 * photometric)
        if rng.random() < 0.5:  # blue-green cast (RGB)
            img = img * np.array([rng.uniform(0.6, 1.0), rng.uniform(0.9, 1.1), rng.uniform(0.9, 1.2)], np.float32)
        if rng.random() < 0.3:  # haze towards an airlight
            t = rng.uniform(1 - 0.4 * photometric, 1.0)
            img = img * t + (1 - t) * np.array([60, 120, 140], np.float32)
    if rng.random() < 0.2:
        img = cv2.GaussianBlur(img, (0, 0), rng.uniform(0.5, 1.5))
    if rng.random() < 0.3:
        img = img + rng.normal(0, rng.uniform(2, 8), img.shape).astype(np.float32)
    if rng.random() < 0.2:  # gray map
        g = img.mean(2, keepdims=True)
        img = np.repeat(g, 3, 2)
    return np.clip(img, 0, 255), b


def random_crop(img, boxes, crop, rng):
    x0, y0 = random_crop_origin(img.shape[0], boxes, crop, rng)
    return img[y0:y0 + crop, x0:x0 + crop], clip_to_crop(boxes, x0, y0, crop)


def random_crop_origin(S, boxes, crop, rng):
    if len(boxes) and rng.random() < 0.75:  # around an object
        k = rng.integers(len(boxes))
        cx, cy = (boxes[k, 1] + boxes[k, 3]) / 2, (boxes[k, 2] + boxes[k, 4]) / 2
        x0 = int(np.clip(cx - crop / 2 + rng.uniform(-crop / 3, crop / 3), 0, S - crop))
        y0 = int(np.clip(cy - crop / 2 + rng.uniform(-crop / 3, crop / 3), 0, S - crop))
    else:
        x0, y0 = int(rng.integers(0, S - crop + 1)), int(rng.integers(0, S - crop + 1))
    return x0, y0


def clip_to_crop(boxes, x0, y0, crop):
    """Boxes in the crop's pixels: cut at its edges, dropped under 40 % visible."""
    out = []
    for c, bx0, by0, bx1, by1 in boxes:
        full = (bx1 - bx0) * (by1 - by0)
        cx0, cy0 = max(bx0, x0), max(by0, y0)
        cx1, cy1 = min(bx1, x0 + crop), min(by1, y0 + crop)
        if cx1 <= cx0 or cy1 <= cy0 or (cx1 - cx0) * (cy1 - cy0) < 0.4 * full:
            continue
        out.append([c, cx0 - x0, cy0 - y0, cx1 - x0, cy1 - y0])
    return np.array(out, np.float32).reshape(-1, 5)


def recalibrate_bn(net, batches, dev, n=60):
    """BatchNorm statistics for the averaged weights: a cumulative mean over n training batches."""
    for m in net.modules():
        if isinstance(m, nn.BatchNorm2d):
            m.reset_running_stats()
            m.momentum = None
    net.train()
    with torch.no_grad():
        for _ in range(n):
            net(next(batches)[0].to(dev))
    net.eval()


def to_tensor(imgs):
    return torch.from_numpy(np.stack(imgs).transpose(0, 3, 1, 2).astype(np.float32) / 255.0)


# ---------------------------------------------------------------- evaluation

def nms_window(pred, min_score, iou=0.5):
    """pred [4+C, N] numpy (cx, cy, w, h, scores) -> list (class, score, x1, y1, x2, y2)."""
    scores = pred[4:].max(0)
    cls = pred[4:].argmax(0)
    keep = scores >= min_score
    if not keep.any():
        return []
    b = pred[:4, keep].T
    boxes = np.stack([b[:, 0] - b[:, 2] / 2, b[:, 1] - b[:, 3] / 2, b[:, 0] + b[:, 2] / 2, b[:, 1] + b[:, 3] / 2], 1)
    sc, cl = scores[keep], cls[keep]
    idx = torchvision.ops.batched_nms(torch.from_numpy(boxes), torch.from_numpy(sc), torch.from_numpy(cl), iou)
    return [(int(cl[i]), float(sc[i]), *boxes[i].tolist()) for i in idx.numpy()]


def metres(lon, lat, lon0, lat0):
    """East/north metres from (lon0, lat0): local ellipsoidal scale, exact enough over a few hundred metres."""
    a, e2 = 6378137.0, 6.69437999014e-3
    p = math.radians(lat0)
    s = 1 - e2 * math.sin(p) ** 2
    n_radius = a / math.sqrt(s)
    m_radius = a * (1 - e2) / s ** 1.5
    return math.radians(lon - lon0) * n_radius * math.cos(p), math.radians(lat - lat0) * m_radius


def detect_survey(windows, truth, run_net, size, min_score):
    """Raw detections of every window -> merged list (class, score, east, north, zoom)."""
    lon0, lat0 = truth["origin"][1], truth["origin"][0]
    r = size / float(N_TILES * TILE)
    raw = []
    for img, _, (z, wx, wy) in windows:
        for c, sc, x1, y1, x2, y2 in nms_window(run_net(img), min_score):
            X0, Y0 = wx * TILE + x1 / r, wy * TILE + y1 / r
            X1, Y1 = wx * TILE + x2 / r, wy * TILE + y2 / r
            trunc = x1 < 2 or y1 < 2 or x2 > size - 2 or y2 > size - 2  # touches a window edge
            (lonA, latA), (lonB, latB) = pixel_to_lonlat(X0, Y0, z), pixel_to_lonlat(X1, Y1, z)
            e0, n1 = metres(lonA, latA, lon0, lat0)
            e1, n0 = metres(lonB, latB, lon0, lat0)
            raw.append(dict(c=c, s=sc, box=(e0, n0, e1, n1), z=z, trunc=trunc))
    # Merge (spec sect. 8, simplified): same class, IoU >= 0.4 or intersection over the smaller >= 0.7.
    raw.sort(key=lambda d: (d["trunc"], -d["z"], -d["s"]))
    kept = []
    for d in raw:
        dup = False
        for k in kept:
            if k["c"] != d["c"]:
                continue
            a, b = d["box"], k["box"]
            iw = min(a[2], b[2]) - max(a[0], b[0])
            ih = min(a[3], b[3]) - max(a[1], b[1])
            if iw <= 0 or ih <= 0:
                continue
            inter = iw * ih
            aa = (a[2] - a[0]) * (a[3] - a[1])
            ab = (b[2] - b[0]) * (b[3] - b[1])
            if inter / (aa + ab - inter) >= 0.4 or inter / min(aa, ab) >= 0.7:
                dup = True
                k["s"] = max(k["s"], d["s"])
                break
        if not dup:
            kept.append(d)
    return [(d["c"], d["s"], (d["box"][0] + d["box"][2]) / 2, (d["box"][1] + d["box"][3]) / 2, d["z"]) for d in kept]


def match(dets, truth, radius=0.10):
    lon0, lat0 = truth["origin"][1], truth["origin"][0]
    gts = []
    for o in truth["objects"]:
        e, n = metres(o["lon"], o["lat"], lon0, lat0)
        gts.append((o["class_id"], e, n))
    pairs = []
    for i, (c, _, e, n, _) in enumerate(dets):
        for j, (gc, ge, gn) in enumerate(gts):
            d = math.hypot(e - ge, n - gn)
            if gc == c and d <= radius:
                pairs.append((d, i, j))
    pairs.sort()
    used_d, used_g, errs = set(), set(), {}
    for d, i, j in pairs:
        if i in used_d or j in used_g:
            continue
        used_d.add(i)
        used_g.add(j)
        errs.setdefault(gts[j][0], []).append(d)
    per = {}
    for c in range(len(CLASSES)):
        nt = sum(1 for g in gts if g[0] == c)
        nd = sum(1 for d in dets if d[0] == c)
        m = len(errs.get(c, []))
        per[c] = (nt, nd, m, errs.get(c, []))
    return per


def evaluate(val_sets, run_net, size, min_score):
    tot = {c: [0, 0, 0, []] for c in range(len(CLASSES))}
    for windows, truth in val_sets:
        per = match(detect_survey(windows, truth, run_net, size, min_score), truth)
        for c, (nt, nd, m, e) in per.items():
            tot[c][0] += nt
            tot[c][1] += nd
            tot[c][2] += m
            tot[c][3] += e
    rows = []
    for c, (nt, nd, m, e) in tot.items():
        rows.append(dict(cls=CLASSES[c], truths=nt, detections=nd, matches=m, recall=m / max(nt, 1),
                         precision=m / max(nd, 1), median_err_m=float(np.median(e)) if e else float("nan")))
    nt = sum(r["truths"] for r in rows)
    nd = sum(r["detections"] for r in rows)
    m = sum(r["matches"] for r in rows)
    allerr = sum((tot[c][3] for c in tot), [])
    rows.append(dict(cls="all", truths=nt, detections=nd, matches=m, recall=m / max(nt, 1), precision=m / max(nd, 1),
                     median_err_m=float(np.median(allerr)) if allerr else float("nan")))
    return rows


# ---------------------------------------------------------------- export

def export_onnx(model, path, size, meta):
    import onnx
    from onnx import numpy_helper
    model.eval()
    model.export = True
    dummy = torch.zeros(1, 3, size, size)
    torch.onnx.export(model, dummy, path, opset_version=12, input_names=["images"], output_names=["output0"],
                      do_constant_folding=True)
    model.export = False
    m = onnx.load(path)
    # torch 1.13 turns identical initialisers into Identity nodes, which OpenCV 4.6 rejects: copy them.
    inits = {i.name: i for i in m.graph.initializer}
    for node in list(m.graph.node):
        if node.op_type == "Identity" and node.input[0] in inits:
            t = numpy_helper.from_array(numpy_helper.to_array(inits[node.input[0]]), node.output[0])
            m.graph.initializer.append(t)
            m.graph.node.remove(node)
    del m.metadata_props[:]
    for k, v in meta.items():
        p = m.metadata_props.add()
        p.key, p.value = k, v
    onnx.checker.check_model(m)
    onnx.save(m, path)


def write_card(report, out_dir):
    """data/models/README.md from the run's report."""
    v = report["validation"]
    rows = "\n".join(f"| {r['cls']} | {r['truths']} | {r['detections']} | {r['matches']} | {r['recall']:.2f} | "
                     f"{r['precision']:.2f} | {r['median_err_m'] * 100:.1f} |" for r in v)
    sizes = ", ".join(f"{k} {a}-{b} m" for k, (a, b) in CLASS_SIZES_M.items())
    text = f"""# seabed_objects.onnx

Object detector for SeaMap tile windows (docs/DETECTION_MODEL.md), trained by `scripts/train_detector.py`
on simulated surveys only (`seamap simulate --objects`).

- Classes (ids in order, also `seabed_objects.names`): {", ".join(CLASSES)}; sizes {sizes}.
- Input: 1 x 3 x {report['imgsz']} x {report['imgsz']} RGB / 255, a window of 3 x 3 tiles of 256 px (INTER_AREA),
  grey 114 under transparent pixels; layer raw.
- Output: **YOLOv8 layout** `[1, {4 + len(CLASSES)}, N]`: cx, cy, w, h in input pixels, then class sigmoids
  (score = max); decoded inside the model. ONNX opset 12, fixed input, runs on OpenCV 4.6 `cv::dnn`
  (max difference to torch {report['cv_max_diff']:.1e}).
- {report['params']} parameters, {report['onnx_mb']} MB.
- Data: training seeds {report['train_seeds'][0]}-{report['train_seeds'][-1]} ({len(report['train_seeds'])} surveys
  of {report.get('frames', 600)} frames, {report.get('objects', 12)} objects each; gray and colour, every third
  `--degrade`, every fourth with JPEG tiles), {report['train_windows']} windows at zooms base and base-2;
  {report['data_minutes']} min to simulate and build.
- Training: {report['steps']} steps of {report['batch']} random {report['crop']} px crops in
  {report['train_minutes']} min on 2 shared CPU cores (torch 1.13, 2 threads).

Validation on held-out seeds {", ".join(str(s) for s in report['val_seeds'])} (windows of both levels, min score
{report['min_score']}, NMS 0.5 per window, duplicates merged across windows and levels, then same-class matches
within 10 cm, greedy one-to-one; error = distance of box centre to truth box centre):

| class | truths | detections | matches | recall | precision | median error (cm) |
| --- | --- | --- | --- | --- | --- | --- |
{rows}
"""
    with open(os.path.join(out_dir, "README.md"), "w") as f:
        f.write(text)


# ---------------------------------------------------------------- the shipped network's weights

def conv_call_order(model, size):
    """The model's Conv2d modules by name, in the order the export traces them (= the ONNX graph's Conv order)."""
    names = {id(m): n for n, m in model.named_modules()}
    order, hooks = [], []
    for m in model.modules():
        if isinstance(m, nn.Conv2d):
            hooks.append(m.register_forward_hook(lambda mod, i, o: order.append(names[id(mod)])))
    was = model.export
    model.export = True
    with torch.no_grad():
        model.eval()(torch.zeros(1, 3, size, size))
    model.export = was
    for h in hooks:
        h.remove()
    return order


def state_from_onnx(path, size=320):
    """Trainable weights recovered from an exported model's initialisers. The export folded each BatchNorm into
    its convolution (W' = W g / sqrt(v + e), b' = beta - m g / sqrt(v + e)), so the BatchNorm comes back as the
    identity with the folded bias as its shift (mean 0, var 1 - eps, weight 1): the same function, and a model
    that fine-tunes with its BatchNorms frozen. Returns (state_dict, class names)."""
    import onnx
    from onnx import numpy_helper
    m = onnx.load(path)
    inits = {i.name: numpy_helper.to_array(i) for i in m.graph.initializer}
    meta = {p.key: p.value for p in m.metadata_props}
    names = parse_names(meta.get("names", ""))
    model = Detector(len(names))
    convs = [n for n in m.graph.node if n.op_type == "Conv"]
    order = conv_call_order(model, size)
    if len(convs) != len(order):
        raise SystemExit(f"{path}: {len(convs)} convolutions, the network has {len(order)}: not this script's model")
    state = {k: v.clone() for k, v in model.state_dict().items()}
    for node, name in zip(convs, order):
        w = inits[node.input[1]]
        b = inits[node.input[2]] if len(node.input) > 2 else np.zeros(w.shape[0], np.float32)
        if tuple(state[name + ".weight"].shape) != w.shape:
            raise SystemExit(f"{path}: {node.name} has weights {w.shape}, {name} expects "
                             f"{tuple(state[name + '.weight'].shape)}")
        state[name + ".weight"] = torch.from_numpy(w.copy())
        if name + ".bias" in state:  # a head's last convolution: its own bias
            state[name + ".bias"] = torch.from_numpy(b.copy())
            continue
        bn = name[:-1] + "1"  # ConvBN: conv at .0, BatchNorm at .1
        eps = 1e-5
        state[bn + ".weight"] = torch.ones(w.shape[0])
        state[bn + ".bias"] = torch.from_numpy(b.copy())
        state[bn + ".running_mean"] = torch.zeros(w.shape[0])
        state[bn + ".running_var"] = torch.full((w.shape[0],), 1.0 - eps)
    return state, names


def parse_names(text):
    """The `names` metadata, "{0: 'tyre', 1: 'crate'}", as a list in id order."""
    pairs = re.findall(r"(\d+)\s*:\s*'([^']*)'", text)
    if not pairs:
        return list(CLASSES)
    return [n for _, n in sorted((int(i), n) for i, n in pairs)]


def weights_path(onnx_path):
    return os.path.splitext(onnx_path)[0] + ".weights.npz"


def load_base(onnx_path, size=320):
    """The base model's weights: the .weights.npz shipped beside it, else recovered from the ONNX itself."""
    w = weights_path(onnx_path)
    state, names = state_from_onnx(onnx_path, size) if not os.path.exists(w) else (None, None)
    if state is None:
        z = np.load(w)
        state = {k: torch.from_numpy(z[k]) for k in z.files if k != "names"}
        names = [str(n) for n in z["names"]]
    return state, names


def recover_weights(onnx_path, size):
    """--recover-weights: the .weights.npz beside the model, checked against cv2.dnn on windows of the shipped
    model's validation kind (a simulated survey's, when one is cached in --work) or on random images."""
    state, names = state_from_onnx(onnx_path, size)
    net = Detector(len(names))
    net.load_state_dict(state)
    rng = np.random.default_rng(0)
    images = [(rng.random((size, size, 3)) * 255).astype(np.uint8) for _ in range(2)]
    worst = check_against_onnx(net, onnx_path, images)
    assert worst < 1e-3, f"recovered weights differ from the ONNX by {worst:.2e}"
    path = weights_path(onnx_path)
    save_state(net, path, names)
    print(f"wrote {path} ({os.path.getsize(path) / 1e6:.2f} MB, {len(names)} classes); torch vs cv2.dnn max "
          f"difference {worst:.2e}", flush=True)
    return 0


def check_against_onnx(net, onnx_path, images):
    """Largest difference between the torch model and cv2.dnn (OpenCV 4.6, as the C++ detector) on RGB images."""
    cvnet = cv2.dnn.readNetFromONNX(onnx_path)
    cvnet.setPreferableBackend(cv2.dnn.DNN_BACKEND_OPENCV)
    cvnet.setPreferableTarget(cv2.dnn.DNN_TARGET_CPU)
    was = net.export
    net.export = True
    net.eval()
    worst = 0.0
    for img in images:
        blob = cv2.dnn.blobFromImage(cv2.cvtColor(img, cv2.COLOR_RGB2BGR), 1 / 255.0, swapRB=True, crop=False)
        cvnet.setInput(blob)
        out_cv = cvnet.forward()
        with torch.no_grad():
            out_t = net(torch.from_numpy(blob)).numpy()
        worst = max(worst, float(np.abs(out_cv - out_t).max()))
    net.export = was
    return worst


# ---------------------------------------------------------------- data packs (to train on another machine)

def write_pack(path, train, val, quality):
    """Windows as JPEG (one channel where the window is gray), boxes, metadata and truth: a file small
    enough to copy to a machine with a GPU that has torch but no SeaMap build."""
    blobs, boxes, meta, survey, truths = [], [], [], [], []
    for k, (windows, truth) in enumerate(train + val):
        truths.append(json.dumps(truth))
        for img, b, m in windows:
            gray = bool((img[:, :, 0] == img[:, :, 1]).all() and (img[:, :, 1] == img[:, :, 2]).all())
            ok, jpg = cv2.imencode(".jpg", img[:, :, 0] if gray else cv2.cvtColor(img, cv2.COLOR_RGB2BGR),
                                   [cv2.IMWRITE_JPEG_QUALITY, quality])
            assert ok
            blobs.append(np.frombuffer(jpg.tobytes(), np.uint8))
            boxes.append(b)
            meta.append(m)
            survey.append(k)
    np.savez(path, jpg=np.concatenate(blobs), jpg_len=np.array([len(b) for b in blobs], np.int64),
             boxes=np.concatenate(boxes).reshape(-1, 5), box_len=np.array([len(b) for b in boxes], np.int64),
             meta=np.array(meta, np.int64), survey=np.array(survey, np.int64), n_train=len(train),
             truths=np.array(truths))
    print(f"pack: {path}, {len(blobs)} windows, {os.path.getsize(path) / 1e6:.1f} MB", flush=True)


def read_pack(path):
    z = np.load(path)
    jpg, jl, bx, bl = z["jpg"], z["jpg_len"], z["boxes"], z["box_len"]
    truths = [json.loads(t) for t in z["truths"]]
    sets = [([], t) for t in truths]
    jo, bo = np.concatenate([[0], np.cumsum(jl)]), np.concatenate([[0], np.cumsum(bl)])
    for i in range(len(jl)):
        img = cv2.imdecode(jpg[jo[i]:jo[i + 1]], cv2.IMREAD_COLOR)  # gray comes back as three equal channels
        sets[z["survey"][i]][0].append((cv2.cvtColor(img, cv2.COLOR_BGR2RGB), bx[bo[i]:bo[i + 1]].copy(),
                                       tuple(int(v) for v in z["meta"][i])))
    n = int(z["n_train"])
    return sets[:n], sets[n:]


def save_state(net, path, names=None):
    """The weights as plain arrays: readable by any torch version (trained on one, exported on another)."""
    extra = {"names": np.array(names)} if names else {}
    np.savez(path, **{k: v.detach().cpu().numpy() for k, v in net.state_dict().items()}, **extra)


def load_state(path):
    if path.endswith(".npz"):
        return {k: torch.from_numpy(v) for k, v in np.load(path).items() if k != "names"}
    return torch.load(path, map_location="cpu")


class CropBatches(torch.utils.data.IterableDataset):
    """Endless batches of `batch` augmented crops, made by the DataLoader's worker processes (each its own random
    stream); a subclass draws one crop in crop_one(rng) -> (img, boxes)."""

    def __iter__(self):
        info = torch.utils.data.get_worker_info()
        rng = np.random.default_rng([self.seed, info.id if info else 0])
        while True:
            imgs, targets = [], []
            for _ in range(self.batch):
                img, boxes = self.crop_one(rng)
                imgs.append(img)
                targets.append(boxes)
            yield to_tensor(imgs), targets


class Crops(CropBatches):
    """Random crops of the samples."""

    def __init__(self, samples, crop, batch, seed):
        self.samples, self.crop, self.batch, self.seed = samples, crop, batch, seed

    def crop_one(self, rng):
        img, boxes = self.samples[rng.integers(len(self.samples))]
        return augment(*random_crop(img, boxes, self.crop, rng), rng)


# ---------------------------------------------------------------- fine-tuning on the operator's review

def world_units(z):
    """Tile pixels of zoom z per world width (Web Mercator), to put windows of all levels on one axis."""
    return float(TILE * (1 << z))


def read_missions(dirs, size, base_names):
    """The windows of `seamap training-data` folders (images/*.png 768 px, labels/*.txt YOLO, manifest.json):
    (class names, [dict(img, boxes [K, 5] class x1 y1 x2 y2 in `size` px, negatives [M, 5], mission, z, x, y,
    ids)]). Classes are matched by name across folders; the base model's keep their ids, new ones follow."""
    names, manifests = list(base_names), {}
    for d in dirs:
        path = os.path.join(d, "manifest.json")
        if not os.path.isfile(path):
            raise SystemExit(f"--from-missions {d}: no manifest.json (expected `seamap training-data` output)")
        man = json.load(open(path))
        for c in man.get("classes", []):
            c = c if isinstance(c, str) else c.get("name", "")
            if c and c not in names:
                names.append(c)
        manifests[d] = man
    out = []
    for d in dirs:
        man = manifests[d]
        classes = [c if isinstance(c, str) else c.get("name", "") for c in man.get("classes", [])]
        for w in man.get("windows", []):
            img_path = os.path.join(d, w["image"])
            img = cv2.imread(img_path, cv2.IMREAD_COLOR)
            if img is None:
                raise SystemExit(f"--from-missions {d}: {w['image']} is not a readable image")
            src = img.shape[0]
            r = size / float(src)
            img = cv2.cvtColor(cv2.resize(img, (size, size), interpolation=cv2.INTER_AREA), cv2.COLOR_BGR2RGB)

            def boxes_of(items, what):
                b = []
                for it in items:
                    c = it["class"]
                    if isinstance(c, str):
                        if c not in classes and c not in names:
                            raise SystemExit(f"{d}/manifest.json: {w['image']}: {what} class {c[:100]!r} is not in "
                                             f"`classes`")
                        c = names.index(c)
                    else:
                        c = names.index(classes[int(c)])
                    x0, y0, x1, y1 = (float(v) * r for v in it["box_px"])
                    b.append([c, x0, y0, x1, y1])
                return np.array(b, np.float32).reshape(-1, 5)

            if "labels" not in w and w.get("label"):  # only the YOLO file: class_id cx cy w h, normalised
                w = dict(w, labels=yolo_labels(os.path.join(d, w["label"]), classes, src))
            out.append(dict(img=img, boxes=boxes_of(w.get("labels", []), "label"),
                            negatives=boxes_of(w.get("negatives", []), "negative"),
                            ids=[str(it.get("id", "")) for it in w.get("labels", [])],
                            mission=f"{d}#{w.get('mission', '')}", z=int(w["z"]), x=int(w["x"]), y=int(w["y"])))
    if not out:
        raise SystemExit("--from-missions: no windows")
    return names, out


def yolo_labels(path, classes, side_px):
    """A YOLO label file as manifest labels (class name, box_px in the window's pixels)."""
    out = []
    for k, line in enumerate(open(path)):
        f = line.split()
        if not f:
            continue
        try:
            c, cx, cy, w, h = int(f[0]), *map(float, f[1:5])
            name = classes[c]
        except (ValueError, IndexError):
            raise SystemExit(f"{path}:{k + 1}: expected 'class_id cx cy w h' (class id in the manifest's "
                             f"classes, numbers normalised), got {line.strip()[:100]!r}")
        out.append({"class": name, "box_px": [(cx - w / 2) * side_px, (cy - h / 2) * side_px,
                                              (cx + w / 2) * side_px, (cy + h / 2) * side_px], "id": ""})
    return out


def split_by_position(windows, val_fraction, size):
    """Held-out ground, not held-out windows: per mission, the far part along its longest axis (holding about
    `val_fraction` of the labelled objects) is validation. Validation windows lie wholly inside it; the
    training windows that reach into it are greyed out there, so training never sees a validation pixel."""
    train, val = [], []
    by_mission = {}
    for w in windows:
        by_mission.setdefault(w["mission"], []).append(w)
    n_tiles_px = N_TILES * TILE
    for mission, ws in by_mission.items():
        def span(w):  # window extent in world fractions
            u = world_units(w["z"])
            return (w["x"] * TILE / u, w["y"] * TILE / u, (w["x"] * TILE + n_tiles_px) / u,
                    (w["y"] * TILE + n_tiles_px) / u)

        centres = []  # labelled objects' centres in world fractions
        for w in ws:
            x0, y0, x1, y1 = span(w)
            for b in w["boxes"]:
                centres.append((x0 + (b[1] + b[3]) / 2 / size * (x1 - x0), y0 + (b[2] + b[4]) / 2 / size * (y1 - y0)))
        spans = np.array([span(w) for w in ws])
        axis = 0 if spans[:, 2].max() - spans[:, 0].min() >= spans[:, 3].max() - spans[:, 1].min() else 1
        if val_fraction <= 0 or not centres:
            train += ws
            continue
        # Each object once (it is labelled in every window and level that holds it): centres to ~5 cm.
        unit = 0.05 / 4.0075e7
        pos = np.array(sorted({(round(c[0] / unit), round(c[1] / unit)) for c in centres}))[:, axis] * unit
        cut = float(np.quantile(pos, 1 - val_fraction))
        for w in ws:
            lo, hi = span(w)[axis], span(w)[axis + 2]
            if lo >= cut:
                val.append(w)
                continue
            if hi > cut:  # grey out the part beyond the cut, drop boxes that lose more than 60 %
                k = int(math.floor((cut - lo) / (hi - lo) * size))
                b = w["boxes"].copy()
                # A held-out object (centre beyond the cut) reaching back over it is greyed out whole.
                for row in b:
                    if (row[1 + axis] + row[3 + axis]) / 2 >= k:
                        k = min(k, int(math.floor(row[1 + axis])))
                k = max(k, 0)
                img = w["img"].copy()
                if axis == 0:
                    img[:, k:] = GREY
                else:
                    img[k:, :] = GREY
                keep, keep_ids = [], []
                for row, oid in zip(b, w["ids"] or [""] * len(b)):
                    a0, a1 = row[1 + axis], row[3 + axis]
                    vis = (min(a1, k) - a0) / max(a1 - a0, 1e-6)
                    if vis >= 0.4:
                        row[3 + axis] = min(a1, k)
                        keep.append(row)
                        keep_ids.append(oid)
                w = dict(w, img=img, boxes=np.array(keep, np.float32).reshape(-1, 5), ids=keep_ids,
                         negatives=w["negatives"][w["negatives"][:, 1 + axis] < k] if len(w["negatives"]) else
                         w["negatives"])
            train.append(w)
    return train, val


def extend_classes(state, old_nc, new_nc, seed=0):
    """The class head for new_nc classes: the old classes' rows kept as they are, new rows small and with the
    focal-loss prior's bias (a low score everywhere until trained)."""
    g = torch.Generator().manual_seed(seed)
    for k in list(state):
        if k.startswith("heads.") and ".cls.1." in k:
            v = state[k]
            if v.shape[0] != old_nc:
                raise SystemExit(f"the base model's class head {k} has {v.shape[0]} rows, expected {old_nc}")
            if k.endswith("weight"):
                extra = torch.randn((new_nc - old_nc,) + tuple(v.shape[1:]), generator=g) * 0.01
            else:
                extra = torch.full((new_nc - old_nc,), -4.6)
            state[k] = torch.cat([v, extra.to(v.dtype)], 0)
    return state


def window_scale_m(w):
    """Metres per input pixel of a `size` px window at the window's latitude."""
    n = 1 << w["z"]
    lat = math.degrees(math.atan(math.sinh(math.pi * (1 - 2 * (w["y"] + 1.5) / n))))
    return 156543.03392 * math.cos(math.radians(lat)) / n


def validate_windows(val, run_net, size, names, thresholds):
    """Per class at each score threshold: objects found on the held-out ground. An object (one label id, seen in
    several windows and levels) counts once; found when some window's detection of its class overlaps its box
    with IoU >= 0.5. A detection with no label of its class at IoU >= 0.3 is a false one, counted once per place
    (duplicates across windows within 10 cm merged)."""
    raw = []  # (window index, class, score, box)
    for i, w in enumerate(val):
        for c, sc, x1, y1, x2, y2 in nms_window(run_net(w["img"]), min(thresholds)):
            raw.append((i, c, sc, (x1, y1, x2, y2)))
    objects = {}  # (mission, id or place) -> class
    for w in val:
        for b, oid in zip(w["boxes"], w["ids"] or [""] * len(w["boxes"])):
            objects.setdefault((w["mission"], oid or ground_key(w, b, size)), int(b[0]))

    table = {}
    for t in thresholds:
        found, false = set(), {}
        for i, c, sc, box in raw:
            if sc < t:
                continue
            w = val[i]
            ids = w["ids"] or [""] * len(w["boxes"])
            best, best_iou = None, 0.0
            for b, oid in zip(w["boxes"], ids):
                if int(b[0]) != c:
                    continue
                v = box_iou(box, b[1:5])
                if v > best_iou:
                    best, best_iou = (w["mission"], oid or ground_key(w, b, size)), v
            if best is not None and best_iou >= 0.5:
                found.add(best)
            elif best is None or best_iou < 0.3:
                false[(w["mission"], c, ground_key(w, [c, *box], size))] = 1
        rows = {}
        for c, name in enumerate(names):
            nt = sum(1 for k, v in objects.items() if v == c)
            nf = sum(1 for k in found if objects.get(k) == c)
            nfalse = sum(1 for k in false if k[1] == c)
            rows[name] = dict(truths=nt, found=nf, false=nfalse)
        table[t] = rows
    return table


def ground_key(w, b, size):
    """A place on the ground to 10 cm (for objects and false detections without an id)."""
    m = window_scale_m(w) * N_TILES * TILE / size
    x0 = w["x"] * TILE * window_scale_m(w)
    y0 = w["y"] * TILE * window_scale_m(w)
    return (round((x0 + (b[1] + b[3]) / 2 * m) / 0.1), round((y0 + (b[2] + b[4]) / 2 * m) / 0.1))


def summarise(rows):
    nt = sum(r["truths"] for r in rows.values())
    nf = sum(r["found"] for r in rows.values())
    nfalse = sum(r["false"] for r in rows.values())
    rec = nf / nt if nt else float("nan")
    prec = nf / (nf + nfalse) if nf + nfalse else float("nan")
    return nt, nf, nfalse, rec, prec


def replay_windows(a, size):
    """Simulated windows of the shipped classes, so fine-tuning does not forget them: from the shipped
    training pack (--replay-pack), else simulated here from the shipped training seeds (never the bench's)."""
    out = []
    if a.replay_pack:
        train, _ = read_pack(a.replay_pack)
        for windows, _ in train:
            out += [dict(img=img, boxes=b, negatives=np.zeros((0, 5), np.float32)) for img, b, _ in windows]
        return out
    for k in range(a.replay_surveys):
        seed = 1000 + k
        d = make_survey(a.seamap, a.work, seed, k % 2 == 1, k % 3 == 2, a.replay_frames, 12,
                        "jpg" if k % 4 == 3 else "png")
        windows, _ = survey_windows(d, size)
        out += [dict(img=img, boxes=b, negatives=np.zeros((0, 5), np.float32)) for img, b, _ in windows]
    # Look-alikes that are no object (rock rings, pipe pieces, dark rocks: `simulate --clutter`), unlabelled, so
    # every crop of them says "nothing here" to the new class too. Seeds 1040+: never a bench's or validation's.
    for k in range(a.replay_clutter_surveys):
        d = make_survey(a.seamap, a.work, 1040 + k, True, False, a.replay_frames, 12, "png", clutter=12)
        windows, _ = survey_windows(d, size)
        out += [dict(img=img, boxes=b, negatives=np.zeros((0, 5), np.float32)) for img, b, _ in windows]
    return out


def mine_confusions(net_fn, windows, new_ids, min_score=0.25, iou_match=0.5):
    """Hard negatives for the new classes: (window index, box [class, x0, y0, x1, y1]) wherever the current net
    calls something a new class that no label of that class is (an old class's object, a look-alike, texture).
    The window keeps its labels, so a rock taken for a drum is trained as a rock and not a drum."""
    out = []
    for i, w in enumerate(windows):
        for c, sc, x1, y1, x2, y2 in nms_window(net_fn(w["img"]), min_score):
            if c not in new_ids:
                continue
            if any(int(b[0]) == c and box_iou((x1, y1, x2, y2), b[1:5]) >= iou_match for b in w["boxes"]):
                continue
            out.append((i, np.array([c, x1, y1, x2, y2], np.float32)))
    return out


def box_iou(a, b):
    iw = min(a[2], b[2]) - max(a[0], b[0])
    ih = min(a[3], b[3]) - max(a[1], b[1])
    if iw <= 0 or ih <= 0:
        return 0.0
    inter = iw * ih
    return inter / ((a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter)


def per_class_thresholds(table, thresholds, names, fallback, min_objects):
    """{class: score}: each class with at least `min_objects` objects on the held-out ground at the threshold of
    its own best F1 (the middle of the best range: few objects, a flat F1); the others at `fallback` (the base
    model's own, so a fine-tune on a review of other classes cannot move their operating point)."""
    out = {}
    for c, name in enumerate(names):
        nt = table[thresholds[0]][name]["truths"] if table else 0
        if nt < min_objects:
            out[name] = fallback.get(name, fallback[None])
            continue

        def f1(t):
            r = table[t][name]
            return 2 * r["found"] / max(nt + r["found"] + r["false"], 1)
        best = max(f1(t) for t in thresholds)
        tied = [t for t in thresholds if f1(t) >= best - 1e-9]
        out[name] = tied[len(tied) // 2]
    return out


class MixedCrops(CropBatches):
    """Batches of augmented crops: `share` of them from the operator's windows (a third of those around a
    rejected detection, a hard negative), the rest from simulated windows of the shipped classes."""

    def __init__(self, review, replay, share, crop, batch, seed, hard_share=0.0):
        self.review, self.replay, self.share = review, replay, share
        self.crop, self.batch, self.seed = crop, batch, seed
        self.hard, self.hard_share = [], hard_share  # (window, box) mined by mine_confusions, filled while training

    def crop_one(self, rng):
        if self.hard and rng.random() < self.hard_share:  # a confusion of the new head, its labels kept
            w, box = self.hard[rng.integers(len(self.hard))]
            return augment(*crop_around(w["img"], w["boxes"], box, self.crop, rng), rng)
        pool = self.review if (not self.replay or rng.random() < self.share) else self.replay
        w = pool[rng.integers(len(pool))]
        boxes = w["boxes"]
        if len(w["negatives"]) and rng.random() < 0.33:
            img, boxes = crop_around(w["img"], boxes, w["negatives"][rng.integers(len(w["negatives"]))], self.crop,
                                     rng)
        else:
            img, boxes = random_crop(w["img"], boxes, self.crop, rng)
        return augment(img, boxes, rng)


def crop_around(img, boxes, centre_box, crop, rng):
    """A crop holding `centre_box` (a hard negative), labels clipped as random_crop does."""
    x0, y0 = crop_around_origin(img.shape[0], centre_box, crop, rng)
    return img[y0:y0 + crop, x0:x0 + crop], clip_to_crop(boxes, x0, y0, crop)


def crop_around_origin(S, centre_box, crop, rng):
    cx, cy = (centre_box[1] + centre_box[3]) / 2, (centre_box[2] + centre_box[4]) / 2
    x0 = int(np.clip(cx - crop / 2 + rng.uniform(-crop / 4, crop / 4), 0, S - crop))
    y0 = int(np.clip(cy - crop / 2 + rng.uniform(-crop / 4, crop / 4), 0, S - crop))
    return x0, y0


def freeze_batchnorm(model):
    """The base model's BatchNorms are its folded biases (state_from_onnx): kept in eval mode, their scale and
    shift train like any weight, and a batch of 8 crops never overwrites the statistics."""
    for m in model.modules():
        if isinstance(m, nn.BatchNorm2d):
            m.eval()


def class_sizes_from_labels(windows, names, size, base_sizes):
    """Size range [min, max] in metres per class: the base model's, and for new classes the labels' longest
    sides (10 % margin)."""
    sizes = {k: list(v) for k, v in base_sizes.items() if k in names}
    seen = {}
    for w in windows:
        m = window_scale_m(w) * N_TILES * TILE / size
        for b in w["boxes"]:
            name = names[int(b[0])]
            if name in sizes:
                continue
            side = max(b[3] - b[1], b[4] - b[2]) * m
            touches = min(b[1], b[2]) < 2 or max(b[3], b[4]) > size - 2
            if not touches:
                seen.setdefault(name, []).append(side)
    for name, v in seen.items():
        sizes[name] = [round(min(v) * 0.9, 2), round(max(v) * 1.1, 2)]
    return sizes


def finetune(a):
    """--from-missions: the base model fine-tuned on the operator's reviewed windows (see module doc)."""
    t_start = time.time()
    cpu_start = time.process_time()
    size = a.imgsz
    base_state, base_names = load_base(a.base, size)
    names, windows = read_missions(a.from_missions, size, base_names)
    train_w, val_w = split_by_position(windows, a.val_fraction, size)
    n_labels = {n: 0 for n in names}
    for w in train_w:
        for b in w["boxes"]:
            n_labels[names[int(b[0])]] += 1
    print(f"review: {len(windows)} windows of {len({w['mission'] for w in windows})} missions; "
          f"{len(train_w)} to train, {len(val_w)} held out by position; labels in training windows: "
          + ", ".join(f"{k} {v}" for k, v in n_labels.items()), flush=True)
    missing = [n for n in names[len(base_names):] if n_labels[n] == 0]
    if missing:
        raise SystemExit(f"--from-missions: no training label of the new class(es) {', '.join(missing)}")
    replay = replay_windows(a, size) if a.replay_share > 0 else []
    print(f"replay: {len(replay)} simulated windows of the shipped classes", flush=True)
    t_data = time.time() - t_start

    base_meta = onnx_metadata(a.base)
    base_sizes = json.loads(base_meta.get("seamap.class_sizes_m", json.dumps(CLASS_SIZES_M)))
    base_min_score = float(base_meta.get("seamap.min_score", a.min_score))
    model = Detector(len(names))
    model.load_state_dict(extend_classes(base_state, len(base_names), len(names)))
    # Few examples: the backbone and neck stay as shipped (their features found the old classes), the heads
    # learn; --train all trains every layer (7x the CPU a step).
    heads_only = a.train == "heads"
    for n, p in model.named_parameters():
        p.requires_grad = not heads_only or n.startswith("heads.")
    opt = torch.optim.AdamW([p for p in model.parameters() if p.requires_grad], lr=a.lr, weight_decay=5e-4)
    ema = torch.optim.swa_utils.AveragedModel(model, avg_fn=lambda e, m, n: 0.99 * e + 0.01 * m)
    loader = dict(num_workers=a.workers, persistent_workers=True, prefetch_factor=4) if a.workers else {}
    crops = MixedCrops(train_w, replay, a.replay_share if replay else 1.0, a.crop, a.batch, 0, a.hard_share)
    batches = iter(torch.utils.data.DataLoader(crops, batch_size=None, **loader))
    new_ids = set(range(len(base_names), len(names)))
    mine_at = sorted(a.mine_at) if new_ids and a.hard_share > 0 else []
    mined = []  # (fraction of the budget, hard negatives found)
    # The budget: --minutes of wall time or 2 x --minutes of this process's CPU time (2 free cores spend 2
    # CPU-minutes a minute), whichever ends first. An explicit --cpu-minutes is the whole budget: on a shared
    # machine the wall time says how loaded it was, the CPU time (every thread of this process; the crops are
    # made in it, --workers 0) is what the fine-tune costs.
    t0, c0 = time.time(), time.process_time()
    wall_budget = a.minutes * 60 if not a.cpu_minutes else math.inf
    cpu_budget = (a.cpu_minutes if a.cpu_minutes else 2 * a.minutes) * 60
    step = 0

    def spent():
        return max((time.time() - t0) / wall_budget, (time.process_time() - c0) / cpu_budget)

    while spent() < 1:
        frac = spent()
        if mine_at and frac >= mine_at[0]:
            # What the new head confuses now (old classes' objects, look-alikes) becomes a hard negative. The
            # DataLoader runs in this process (--workers 0), so the crops see the list grow.
            mine_at.pop(0)
            model.eval()
            model.export = True

            def run_now(img):
                with torch.no_grad():
                    return model(to_tensor([img.astype(np.float32)]))[0].numpy()
            pool = train_w + replay
            found = mine_confusions(run_now, pool, new_ids)
            model.export = False
            crops.hard = [(pool[i], box) for i, box in found]
            on_replay = sum(1 for i, _ in found if i >= len(train_w))
            mined.append((round(frac, 2), len(found), on_replay))
            print(f"step {step}: {len(found)} hard negatives of the new class(es) mined ({on_replay} on the "
                  f"simulated windows of the shipped classes)", flush=True)
        for g in opt.param_groups:
            g["lr"] = a.lr * (0.05 + 0.95 * 0.5 * (1 + math.cos(math.pi * frac))) * min(1.0, (step + 1) / 50)
        imgs, targets = next(batches)
        model.train()
        freeze_batchnorm(model)
        if heads_only:
            with torch.no_grad():
                feats = model.features(imgs)
            loss, npos = loss_fn(model.decode(feats), targets)
        else:
            loss, npos = loss_fn(model(imgs), targets)
        opt.zero_grad()
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 10.0)
        opt.step()
        ema.update_parameters(model)
        step += 1
        if step % 50 == 0:
            print(f"step {step} {time.time() - t0:.0f} s ({time.process_time() - c0:.0f} CPU-s) loss "
                  f"{loss.item():.3f} pos {npos}", flush=True)
    t_train = time.time() - t0
    net = (ema.module if step else model).eval()

    # Validation on the held-out ground: the score threshold with the best F1 over all classes.
    net.export = True

    def run_torch(img):
        with torch.no_grad():
            return net(to_tensor([img.astype(np.float32)]))[0].numpy()

    thresholds = [round(0.25 + 0.05 * k, 2) for k in range(12)]
    table = validate_windows(val_w, run_torch, size, names, thresholds) if val_w else {}
    min_score = base_min_score
    if table:
        def f1(t):
            _, nf, nfalse, _, _ = summarise(table[t])
            nt = sum(r["truths"] for r in table[t].values())
            return 2 * nf / max(nt + nf + nfalse, 1)
        best = max(f1(t) for t in thresholds)
        tied = [t for t in thresholds if f1(t) >= best - 1e-9]
        min_score = tied[len(tied) // 2]  # the middle of the best range: few held-out objects, a flat F1
    # A threshold per class: the classes the review holds enough of validated on their own, the others kept at
    # the base model's (its own per-class ones, else its single one).
    fallback = {None: base_min_score}
    fallback.update(zip(base_names, json.loads(base_meta["seamap.class_min_scores"]))
                    if base_meta.get("seamap.class_min_scores", "").startswith("[")
                    else json.loads(base_meta.get("seamap.class_min_scores", "{}")).items())
    class_scores = per_class_thresholds(table, thresholds, names, fallback, a.class_min_objects)
    class_validation = {n: table[class_scores[n]][n] for n in names} if table else {}
    net.export = False

    out = a.out if a.out.endswith(".onnx") else os.path.join(a.out, "seabed_objects.onnx")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    sizes = class_sizes_from_labels(windows, names, size, base_sizes)
    meta = {
        "names": "{" + ", ".join(f"{i}: '{n}'" for i, n in enumerate(names)) + "}",
        "stride": str(max(STRIDES)),
        "imgsz": f"[{size}, {size}]",
        "task": "detect",
        "seamap.class_sizes_m": json.dumps(sizes),
        "seamap.layer": base_meta.get("seamap.layer", "raw"),
        "seamap.layout": "yolov8",
        "seamap.min_score": str(min_score),
        "seamap.class_min_scores": json.dumps(class_scores),
        "seamap.base": os.path.basename(a.base),
        "seamap.finetune_missions": ",".join(os.path.basename(os.path.normpath(d)) for d in a.from_missions),
    }
    export_onnx(net, out, size, meta)
    save_state(net, weights_path(out), names)
    worst = check_against_onnx(net, out, [w["img"] for w in (val_w or train_w)[:4]])
    print(f"cv2.dnn vs torch: max difference {worst:.2e}", flush=True)
    assert worst < 1e-3, "cv2.dnn does not match torch"
    with open(os.path.splitext(out)[0] + ".names", "w") as f:
        f.write("\n".join(names) + "\n")
    report = dict(base=a.base, missions=a.from_missions, classes=names, class_sizes_m=sizes, steps=step,
                  batch=a.batch, crop=a.crop, lr=a.lr, train_minutes=round(t_train / 60, 2),
                  data_minutes=round(t_data / 60, 2), cpu_minutes=round((time.process_time() - cpu_start) / 60, 2),
                  train_windows=len(train_w), val_windows=len(val_w), replay_windows=len(replay),
                  replay_share=a.replay_share if replay else 1.0, train=a.train, train_labels=n_labels, min_score=min_score,
                  validation=table.get(min_score, {}) if table else {}, cv_max_diff=worst,
                  class_min_scores=class_scores, class_validation=class_validation, mined=mined,
                  hard_share=a.hard_share, replay_clutter_surveys=a.replay_clutter_surveys,
                  thresholds={str(t): summarise(table[t])[3:] for t in thresholds} if table else {})
    json.dump(report, open(os.path.splitext(out)[0] + ".report.json", "w"), indent=1)
    write_finetune_card(report, out)
    print(f"wrote {out} ({len(names)} classes, min score {min_score}), its card and weights", flush=True)
    return 0


# ---------------------------------------------------------------- robust fine-tune of the shipped model

ROBUST_SEED0 = 1100  # never a bench's (1, 2, 3101-3109, 3201-3202), the validation's (2000+) or the replay's (1000+)


def robust_plan(k):
    """The k-th domain-randomised survey (seed 1100 + k): the stress conditions the shipped data lacked, drawn
    from the seed so the recipe re-runs the same. Every survey draws altitude, water and camera; half carry
    sediment over the objects, half look-alikes (unlabelled: background)."""
    seed = ROBUST_SEED0 + k
    rng = random.Random(seed)
    extra, tag = [], []
    lo, hi = rng.choice([(1.6, 2.0), (1.6, 2.0), (1.0, 1.4), (2.4, 3.0), (3.3, 4.0)])  # 1-4 m, most usual
    extra += ["--altitude-min", str(lo), "--altitude-max", str(hi)]
    tag.append(f"a{lo:g}")
    for opt, top in (("--vignetting", 0.9), ("--color-cast", 0.9), ("--haze", 0.7)):  # lamp falloff, cast, haze
        if rng.random() < 0.6:
            extra += [opt, f"{rng.uniform(0.1, top):.2f}"]
    if rng.random() < 0.5:
        extra += ["--noise", f"{rng.uniform(1, 4):.1f}"]
    if rng.random() < 0.35:
        extra += ["--blur", str(rng.randint(2, 6))]
        tag.append("blur")
    if rng.random() < 0.5:
        extra += ["--image-format", "jpg", "--jpeg-quality", str(rng.randint(50, 95))]
    if k % 2 == 0:  # half-buried objects: sediment over 20-60 % of their height
        extra += ["--bury", f"{0.2 + 0.4 * rng.random():.2f}"]
        tag.append("bury")
    clutter = 12 if k % 4 in (1, 2) else 0  # look-alikes: rock rings, pipe pieces, dark rocks
    return dict(seed=seed, color=rng.random() < 0.8, degrade=False, tile_format="png", objects=20, clutter=clutter,
                extra=extra, tag="_".join(tag))


LOOKALIKE = len(CLASSES)  # training-only class of the look-alikes (rock rings, pipe pieces, dark rocks)
LOOKALIKE_PHOTOMETRIC = 0.25  # brightness/contrast jitter and haze on crops centred on a look-alike (1: usual)


IGNORED = -1  # a label region taught neither as an object nor as background (detector_net.loss_fn)
ROCK = CLASSES.index("rock")


def robust_labels(full, x0, y0, crop):
    """The crop's labels from a window's whole (uncut) boxes: an object at least 40 % visible as random_crop
    labels it; one cut to less (a pipe's end at the crop's edge) and a look-alike cut at all (a pipe piece cut
    there looks like a real pipe's end) are IGNORED, so neither is taught as background or as a look-alike."""
    out = []
    for c, bx0, by0, bx1, by1 in full:
        cx0, cy0, cx1, cy1 = max(bx0, x0), max(by0, y0), min(bx1, x0 + crop), min(by1, y0 + crop)
        if cx1 <= cx0 or cy1 <= cy0:
            continue
        visible = (cx1 - cx0) * (cy1 - cy0) / max((bx1 - bx0) * (by1 - by0), 1e-6)
        whole = visible >= (0.99 if c == LOOKALIKE else 0.4)
        out.append([c if whole else IGNORED, cx0 - x0, cy0 - y0, cx1 - x0, cy1 - y0])
    return np.array(out, np.float32).reshape(-1, 5)


class RobustCrops(CropBatches):
    """Batches of augmented crops for --robust: `share` of them from the domain-randomised windows, the rest from
    the shipped training's (replay). A third of the crops of windows with look-alikes centre on one, with the
    photometric jitter cut to LOOKALIKE_PHOTOMETRIC (the albedo cue kept); `bury_share` of all crops centre on an
    object of a --bury survey (half-buried objects weighted up), `rock_share` on a rock of a robust window. Labels
    by robust_labels (cut objects and look-alikes ignored) from the windows' whole boxes."""

    def __init__(self, robust, replay, share, crop, batch, seed, bury_share, rock_share=0.0):
        self.robust, self.replay, self.share = robust, replay, share
        self.crop, self.batch, self.seed, self.bury_share = crop, batch, seed, bury_share
        self.rock_share = rock_share
        self.buried = [w for w in robust if w["buried"] and (w["boxes"][:, 0] < LOOKALIKE).any()]
        self.rocky = [w for w in robust if (w["boxes"][:, 0] == ROCK).any()]

    def cut(self, w, x0, y0, rng, photometric=1.0):
        img = w["img"][y0:y0 + self.crop, x0:x0 + self.crop]
        return augment(img, robust_labels(w["full"], x0, y0, self.crop), rng, photometric)

    def around(self, w, cls, rng):  # a crop around one labelled box of class cls (< LOOKALIKE: any object)
        objs = w["boxes"][(w["boxes"][:, 0] == cls) if cls < LOOKALIKE else (w["boxes"][:, 0] < LOOKALIKE)]
        return self.cut(w, *crop_around_origin(w["img"].shape[0], objs[rng.integers(len(objs))], self.crop, rng),
                        rng)

    def crop_one(self, rng):
        u = rng.random()
        if self.buried and u < self.bury_share:  # around a half-buried object
            return self.around(self.buried[rng.integers(len(self.buried))], LOOKALIKE, rng)
        if self.rocky and u < self.bury_share + self.rock_share:  # around a rock (the class the look-alikes cost)
            return self.around(self.rocky[rng.integers(len(self.rocky))], ROCK, rng)
        pool = self.robust if (not self.replay or rng.random() < self.share) else self.replay
        w = pool[rng.integers(len(pool))]
        S = w["img"].shape[0]
        if len(w["negatives"]) and rng.random() < 0.33:
            neg = w["negatives"][rng.integers(len(w["negatives"]))]
            return self.cut(w, *crop_around_origin(S, neg, self.crop, rng), rng, LOOKALIKE_PHOTOMETRIC)
        return self.cut(w, *random_crop_origin(S, w["boxes"], self.crop, rng), rng)


def head_rows(state, nc):
    """The state with the class head cut to its first nc rows (a sigmoid per class: the others' scores unchanged)."""
    return {k: (v[:nc] if k.startswith("heads.") and ".cls.1." in k else v) for k, v in state.items()}


def truth_boxes(items, z, wx, wy, r, size, min_visible=0.4, cut=True):
    """Boxes [class, x0, y0, x1, y1] (window px) of truth items (objects or negatives) in window (z, wx, wy);
    cut=False: every item the window shows, its whole box (beyond the window's edges too)."""
    x0, y0 = wx * TILE, wy * TILE
    out = []
    for o in items:
        pts = [lonlat_to_pixel(lon, lat, z) for lon, lat in o["footprint_lonlat"]]
        bx0, by0 = min(p[0] for p in pts), min(p[1] for p in pts)
        bx1, by1 = max(p[0] for p in pts), max(p[1] for p in pts)
        cx0, cy0 = max(bx0, x0), max(by0, y0)
        cx1, cy1 = min(bx1, x0 + N_TILES * TILE), min(by1, y0 + N_TILES * TILE)
        if cx1 <= cx0 or cy1 <= cy0 or (cut and (cx1 - cx0) * (cy1 - cy0) < min_visible * (bx1 - bx0) * (by1 - by0)):
            continue
        if not cut:
            cx0, cy0, cx1, cy1 = bx0, by0, bx1, by1
        out.append([o.get("class_id", 0), (cx0 - x0) * r, (cy0 - y0) * r, (cx1 - x0) * r, (cy1 - y0) * r])
    return np.array(out, np.float32).reshape(-1, 5)


def robust_finetune(a):
    """--robust N: the shipped network (--base, its .weights.npz) fine-tuned on N domain-randomised surveys mixed
    with the shipped training distribution (replay), every layer or the heads (+ neck) at a low learning rate,
    BatchNorms frozen (they are the export's folded biases), EMA of the weights; exported with the base's layout
    and metadata beside a report. The network's windows and labels as the shipped training made them; look-alikes
    (`--clutter`) are labelled as a training-only class of their own (an extra row of the class head, LOOKALIKE,
    dropped at export: the model keeps the shipped 5-class layout), and a third of their windows' crops centre on
    one with a milder photometric jitter; --bury-share of the crops centre on a half-buried object, --rock-share
    on a rock; objects cut to under 40 % and look-alikes cut at all by a crop's edge are ignored (robust_labels).
    --resume: start from an earlier run's state (its robust_ema.npz) instead of --base's weights."""
    t_start, cpu_start = time.time(), time.process_time()
    size = a.imgsz
    base_state, names = load_base(a.base, size)
    if names != CLASSES:
        raise SystemExit(f"--robust: --base {a.base[:100]} has classes {names}, expected the shipped {CLASSES}")
    base_meta = onnx_metadata(a.base)

    def windows_of(p):
        d = make_survey(a.seamap, a.work, p["seed"], p["color"], p["degrade"], a.frames, p["objects"],
                        p["tile_format"], p.get("clutter", 0), p.get("extra", ()), p.get("tag", ""))
        windows, truth = survey_windows(d, size)
        negatives = [dict(o, class_id=LOOKALIKE) for o in truth.get("negatives", [])]
        buried = "--bury" in p.get("extra", ())
        out = []
        for img, boxes, (z, wx, wy) in windows:
            r = size / float(N_TILES * TILE)
            neg = truth_boxes(negatives, z, wx, wy, r, size, 0.6) if negatives else np.zeros((0, 5), np.float32)
            if negatives:  # labelled as the look-alike class, clipped as the objects are
                boxes = np.concatenate([boxes, truth_boxes(negatives, z, wx, wy, r, size)])
            full = truth_boxes(truth["objects"] + negatives, z, wx, wy, r, size, cut=False)  # for robust_labels
            out.append(dict(img=img, boxes=boxes, full=full, negatives=neg, buried=buried))
        print(f"seed {p['seed']} {p.get('tag', '')}: {len(windows)} windows, {len(truth['objects'])} objects, "
              f"{len(negatives)} look-alikes", flush=True)
        return out

    replay_plan = [dict(seed=1000 + k, color=k % 2 == 1, degrade=k % 3 == 2,
                        tile_format="jpg" if k % 4 == 3 else "png", objects=12 if k < 12 else a.objects)
                   for k in range(a.train_surveys)]
    robust_plans = [robust_plan(k) for k in range(a.robust)]
    replay = [w for p in replay_plan for w in windows_of(p)]
    robust = [w for p in robust_plans for w in windows_of(p)]
    t_data = time.time() - t_start
    print(f"data: {len(robust)} robust windows, {len(replay)} replay windows in {t_data:.0f} s", flush=True)

    dev = torch.device(a.device)  # --device cuda --workers N: the same recipe with many more steps on a GPU
    train_names = CLASSES + ["lookalike"]
    model = Detector(len(train_names))
    if a.resume:  # warm start: an earlier --robust run's state (WORK/robust_ema.npz, the look-alike row kept)
        model.load_state_dict(load_state(a.resume))
    else:
        model.load_state_dict(extend_classes(dict(base_state), len(CLASSES), len(train_names)))
    model.to(dev)
    trainable = {"heads": ("heads.",), "neck": ("heads.", "lat", "td", "down", "pan"), "all": ("",)}[a.train]
    for n, p in model.named_parameters():
        p.requires_grad = n.startswith(trainable)
    params = [p for p in model.parameters() if p.requires_grad]
    print(f"training {a.train}: {sum(p.numel() for p in params)} of "
          f"{sum(p.numel() for p in model.parameters())} parameters", flush=True)
    opt = torch.optim.AdamW(params, lr=a.lr, weight_decay=5e-4)
    ema = torch.optim.swa_utils.AveragedModel(model, avg_fn=lambda e, m, n: 0.995 * e + 0.005 * m)
    crops = RobustCrops(robust, replay, a.replay_share if replay else 1.0, a.crop, a.batch, 0, a.bury_share,
                        a.rock_share)
    print(f"look-alike labels: {sum(int((w['boxes'][:, 0] == LOOKALIKE).sum()) for w in robust)} in windows; "
          f"{len(crops.buried)} windows of --bury surveys, {a.bury_share:.0%} of the crops around their objects; "
          f"{len(crops.rocky)} robust windows with rocks, {a.rock_share:.0%} of the crops around a rock", flush=True)
    sample = [crops.crop_one(np.random.default_rng([1, k]))[1] for k in range(2000)]  # what the labels look like
    labels = np.concatenate(sample)[:, 0]
    ignored = sum(len(b) for b in sample) and float((labels == IGNORED).mean())
    print(f"2000 sample crops: {len(labels)} labels, {ignored:.1%} ignored (cut objects and look-alikes), "
          f"{float((labels == ROCK).mean()):.1%} rocks, {float((labels == LOOKALIKE).mean()):.1%} look-alikes",
          flush=True)
    loader = dict(num_workers=a.workers, persistent_workers=True, prefetch_factor=4) if a.workers else {}
    batches = iter(torch.utils.data.DataLoader(crops, batch_size=None, **loader))
    t0, c0 = time.time(), time.process_time()
    # Whichever ends first: --cpu-minutes of this process's CPU time or --minutes of wall time (a long run on a
    # shared machine must still end in time to be benched).
    cpu_budget = (a.cpu_minutes if a.cpu_minutes else 2 * a.minutes) * 60
    wall_budget = a.minutes * 60
    step = 0

    def spent():
        return max((time.time() - t0) / wall_budget, (time.process_time() - c0) / cpu_budget)

    while spent() < 1:
        frac = spent()
        for g in opt.param_groups:
            g["lr"] = a.lr * (0.05 + 0.95 * 0.5 * (1 + math.cos(math.pi * frac))) * min(1.0, (step + 1) / 100)
        imgs, targets = next(batches)
        model.train()
        freeze_batchnorm(model)
        loss, npos = loss_fn(model(imgs.to(dev, non_blocking=True)), targets)
        opt.zero_grad()
        loss.backward()
        torch.nn.utils.clip_grad_norm_(params, 10.0)
        opt.step()
        ema.update_parameters(model)
        step += 1
        if step % 100 == 0:
            print(f"step {step} {time.time() - t0:.0f} s ({time.process_time() - c0:.0f} CPU-s) loss "
                  f"{loss.item():.3f} pos {npos}", flush=True)
        if step % 1000 == 0:
            save_state(ema.module, os.path.join(a.work, "robust_ema.npz"), train_names)
    t_train, c_train = time.time() - t0, time.process_time() - c0
    trained = (ema.module if step else model).eval().cpu()
    save_state(trained, os.path.join(a.work, "robust_ema.npz"), train_names)
    net = Detector(len(CLASSES))  # the look-alike row dropped: the shipped output layout, never reported
    net.load_state_dict(head_rows(trained.state_dict(), len(CLASSES)))
    net.eval()

    out = a.out if a.out.endswith(".onnx") else os.path.join(a.out, "seabed_objects.onnx")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    data_hash = hashlib.sha256(b"".join(w["img"].tobytes()[:4096] for w in robust + replay)).hexdigest()[:16]
    meta = dict(base_meta)  # the shipped layout, classes, sizes and threshold
    meta.update({"seamap.base": os.path.basename(a.base), "seamap.data_hash": data_hash,
                 "seamap.robust_seeds": ",".join(str(p["seed"]) for p in robust_plans),
                 "seamap.replay_seeds": ",".join(str(p["seed"]) for p in replay_plan)})
    export_onnx(net, out, size, meta)
    save_state(net, weights_path(out), CLASSES)
    with open(os.path.splitext(out)[0] + ".names", "w") as f:
        f.write("\n".join(CLASSES) + "\n")
    worst = check_against_onnx(net, out, [w["img"] for w in robust[:4]])
    print(f"cv2.dnn vs torch: max difference {worst:.2e}", flush=True)
    assert worst < 1e-3, "cv2.dnn does not match torch"
    size_mb = os.path.getsize(out) / 1e6
    assert size_mb <= 4, f"model is {size_mb:.1f} MB, over 4 MB"
    report = dict(base=a.base, train=a.train, lr=a.lr, steps=step, batch=a.batch, crop=a.crop,
                  train_minutes=round(t_train / 60, 2), train_cpu_minutes=round(c_train / 60, 2),
                  data_minutes=round(t_data / 60, 2), cpu_minutes=round((time.process_time() - cpu_start) / 60, 2),
                  robust_surveys=robust_plans, replay_seeds=[p["seed"] for p in replay_plan],
                  robust_windows=len(robust), replay_windows=len(replay), replay_share=a.replay_share,
                  lookalike_labels=sum(int((w["boxes"][:, 0] == LOOKALIKE).sum()) for w in robust),
                  lookalike_photometric=LOOKALIKE_PHOTOMETRIC, bury_share=a.bury_share, rock_share=a.rock_share,
                  resume=a.resume, ignored_label_share=round(ignored, 4),
                  buried_windows=len(crops.buried),
                  frames=a.frames, onnx_mb=round(size_mb, 2), cv_max_diff=worst)
    json.dump(report, open(os.path.splitext(out)[0] + ".report.json", "w"), indent=1)
    print(f"wrote {out}, its weights and {os.path.splitext(out)[0]}.report.json", flush=True)
    return 0


def onnx_metadata(path):
    import onnx
    return {p.key: p.value for p in onnx.load(path).metadata_props}


def write_finetune_card(r, out):
    """A model card beside the fine-tuned model: data, minutes, validation per class."""
    rows = []
    for name, v in r["validation"].items():
        rec = v["found"] / v["truths"] if v["truths"] else float("nan")
        prec = v["found"] / (v["found"] + v["false"]) if v["found"] + v["false"] else float("nan")
        rows.append(f"| {name} | {r['train_labels'].get(name, 0)} | {v['truths']} | {v['found']} | {v['false']} | "
                    f"{rec:.2f} | {prec:.2f} |")
    if r["validation"]:
        nt, nf, nfalse, rec, prec = summarise(r["validation"])
        rows.append(f"| all | {sum(r['train_labels'].values())} | {nt} | {nf} | {nfalse} | {rec:.2f} | {prec:.2f} |")
    table = "\n".join(rows) if rows else "(no held-out windows: `--val-fraction 0`)"
    text = f"""# {os.path.basename(out)}

Fine-tuned by `scripts/train_detector.py --from-missions` from `{os.path.basename(r['base'])}` on an operator's
reviewed missions (docs/DETECTION_MODEL.md, "Fine-tuning on the operator's review").

- Classes (ids in order): {", ".join(r['classes'])}; sizes (m) {json.dumps(r['class_sizes_m'])}.
- Data: {", ".join(os.path.normpath(d) for d in r['missions'])}: {r['train_windows']} training windows,
  {r['val_windows']} held out by position (the far part of each mission along its longest axis), mixed with
  {r['replay_windows']} simulated windows of the shipped classes ({r['replay_share']:.0%} of the crops from the review).
- Training ({r['train']}): {r['steps']} steps of {r['batch']} crops of {r['crop']} px in {r['train_minutes']} min
  ({r['cpu_minutes']} CPU-min in all, data {r['data_minutes']} min), AdamW {r['lr']}, BatchNorm frozen, EMA.
- Metadata `seamap.min_score` = {r['min_score']}: the threshold with the best F1 on the held-out windows;
  `seamap.class_min_scores` = {json.dumps(r.get('class_min_scores', {}))}: each class with enough held-out objects
  at its own best F1, the others at the base model's threshold (what `seamap detect` applies).
- Hard negatives: {r.get('hard_share', 0):.0%} of the crops around what the new class(es) were confused with (mined
  at {", ".join(f"{f:.0%}: {n} ({k} on simulated windows)" for f, n, k in r.get('mined', [])) or "never"}), {r.get('replay_clutter_surveys', 0)} replay survey(s) with look-alikes.
- cv2.dnn vs torch: max difference {r['cv_max_diff']:.1e}.

Held-out validation (objects on the held-out ground, each once; found = a detection of its class at IoU >= 0.5
in some window; false = a detection with no label of its class at IoU >= 0.3, once per 10 cm place):

| class | training labels (in windows) | held-out objects | found | false | recall | precision |
| --- | --- | --- | --- | --- | --- | --- |
{table}
"""
    with open(os.path.splitext(out)[0] + ".md", "w") as f:
        f.write(text)


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seamap", default="build/seamap")
    ap.add_argument("--work", default="/tmp/seamap_train")
    ap.add_argument("--out", default="data/models")
    ap.add_argument("--train-surveys", type=int, default=36)
    ap.add_argument("--val-surveys", type=int, default=2)
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--objects", type=int, default=20, help="objects per survey after the first 12 (3/4 if they do not fit)")
    ap.add_argument("--imgsz", type=int, default=320)
    ap.add_argument("--crop", type=int, default=192)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--lr", type=float, help="learning rate (2e-3, fine-tuning too)")
    ap.add_argument("--minutes", type=float, default=30, help="training wall time; 0: export --resume as it is")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--workers", type=int, default=0, help="processes making the augmented crops")
    ap.add_argument("--device", default="cpu", help="cpu or cuda")
    ap.add_argument("--min-score", type=float, default=0.6,
                    help="validation score, and the model's default (metadata seamap.min_score)")
    ap.add_argument("--resume", help="start from this state_dict (--robust: an earlier run's robust_ema.npz)")
    ap.add_argument("--pack", help="write the windows to this .npz and stop")
    ap.add_argument("--pack-quality", type=int, default=92, help="JPEG quality of the packed windows")
    ap.add_argument("--from-pack", help="train on the windows of this .npz instead of simulating")
    ap.add_argument("--no-export", action="store_true", help="save the state dict and validate with torch only")
    ap.add_argument("--from-missions", nargs="+", metavar="DIR",
                    help="fine-tune --base on these `seamap training-data` folders, write --out (a .onnx)")
    ap.add_argument("--base", default="data/models/seabed_objects.onnx",
                    help="the model to fine-tune; its weights from the .weights.npz beside it, else from the ONNX")
    ap.add_argument("--val-fraction", type=float, default=0.25,
                    help="share of each reviewed mission's objects held out (by position) for validation")
    ap.add_argument("--replay-share", type=float, default=0.5,
                    help="share of the crops from the review; the rest from simulated windows of the old classes")
    ap.add_argument("--replay-pack", help="the old classes' windows from this pack instead of simulating them")
    ap.add_argument("--replay-surveys", type=int, default=4, help="surveys simulated for the old classes")
    ap.add_argument("--replay-frames", type=int, default=300, help="frames of each replay survey")
    ap.add_argument("--replay-clutter-surveys", type=int, default=0,
                    help="replay surveys with look-alikes and no label on them (simulate --clutter 12; off: its "
                         "unlabelled dark rocks taught the rock head to drop real rocks, docs/DETECTION_MODEL.md)")
    ap.add_argument("--hard-share", type=float, default=0.2,
                    help="share of the crops around what the new class(es) are confused with (mined, 0: none)")
    ap.add_argument("--mine-at", type=float, nargs="+", default=[0.3, 0.6],
                    help="fractions of the budget at which the confusions are mined again")
    ap.add_argument("--class-min-objects", type=int, default=3,
                    help="held-out objects a class needs for its own threshold (else the base model's)")
    ap.add_argument("--cpu-minutes", type=float,
                    help="fine-tuning: the budget in CPU time of this process, wall time not counted (default: 2 x --minutes "
                         "or --minutes of wall time, whichever ends first)")
    ap.add_argument("--train", choices=["heads", "neck", "all"], default="heads",
                    help="fine-tuning: train the heads only (default), the heads and the neck, or every layer")
    ap.add_argument("--robust", type=int, default=0, metavar="N",
                    help="fine-tune --base on N domain-randomised surveys (seeds 1100+: altitude 1-4 m, water, "
                         "blur, JPEG 50-95, --bury, --clutter) mixed with --train-surveys of the shipped data; "
                         "writes --out (a .onnx); budget --cpu-minutes (docs/DETECTION_MODEL.md)")
    ap.add_argument("--bury-share", type=float, default=0.2,
                    help="--robust: share of the crops centred on an object of a --bury survey (half-buried)")
    ap.add_argument("--rock-share", type=float, default=0.2,
                    help="--robust: share of the crops centred on a rock of a robust survey")
    ap.add_argument("--recover-weights", action="store_true",
                    help="write --base's weights beside it (.weights.npz), recovered from the ONNX and checked")
    a = ap.parse_args()
    if a.lr is None:
        a.lr = 2e-3  # fine-tuning too: measured so in docs/DETECTION_MODEL.md (bench_new_class, 2026-11-28)

    random.seed(0)
    np.random.seed(0)
    torch.manual_seed(0)
    torch.set_num_threads(a.threads)
    cv2.setNumThreads(1)
    os.makedirs(a.work, exist_ok=True)
    if a.recover_weights:
        return recover_weights(a.base, a.imgsz)
    if a.robust:
        if not a.out.endswith(".onnx") or a.minutes <= 0 or not 0 < a.replay_share <= 1:
            raise SystemExit("--robust: --out must end in .onnx, --minutes be > 0, --replay-share in 0..1 (above 0: "
                             "the share of the crops from the robust surveys)")
        return robust_finetune(a)
    if a.from_missions:
        if not a.out.endswith(".onnx"):
            raise SystemExit(f"--out {a.out[:100]}: expected the fine-tuned model's path, ending in .onnx")
        if a.minutes <= 0 or not 0 <= a.replay_share <= 1 or not 0 <= a.val_fraction < 1:
            raise SystemExit("--minutes must be > 0, --replay-share in 0..1, --val-fraction in 0..1 (below 1)")
        return finetune(a)
    t_start = time.time()

    def plan(seed, k):  # the shipped model's data: 12 objects on the first 12 surveys of each set, then --objects
        return dict(seed=seed, color=k % 2 == 1, degrade=k % 3 == 2, tile_format="jpg" if k % 4 == 3 else "png",
                    objects=12 if k < 12 else a.objects)

    train_plan = [plan(1000 + k, k) for k in range(a.train_surveys)]
    val_plan = [plan(2000 + k, k) for k in range(a.val_surveys)]
    if a.from_pack:
        train, val = read_pack(a.from_pack)
        train_plan = [dict(seed=t["seed"]) for _, t in train]
        val_plan = [dict(seed=t["seed"]) for _, t in val]
    else:
        train, val = [], []
        for p in train_plan + val_plan:
            d = make_survey(a.seamap, a.work, p["seed"], p["color"], p["degrade"], a.frames, p["objects"],
                            p["tile_format"])
            windows, truth = survey_windows(d, a.imgsz)
            truth["seed"] = p["seed"]
            (train if p["seed"] < 2000 else val).append((windows, truth))
            print(f"seed {p['seed']}: {len(windows)} windows, {len(truth['objects'])} objects", flush=True)
    if a.pack:
        write_pack(a.pack, train, val, a.pack_quality)
        return 0
    t_data = time.time() - t_start
    samples = [(img, boxes) for windows, _ in train for img, boxes, _ in windows]
    data_hash = hashlib.sha256(b"".join(img.tobytes()[:4096] for img, _ in samples)).hexdigest()[:16]
    print(f"data: {len(samples)} training windows in {t_data:.0f} s", flush=True)

    dev = torch.device(a.device)
    torch.backends.cudnn.benchmark = True
    model = Detector(len(CLASSES))
    if a.resume:
        model.load_state_dict(load_state(a.resume))
    model.to(dev)
    params = sum(p.numel() for p in model.parameters())
    print(f"model: {params} parameters", flush=True)
    opt = torch.optim.AdamW(model.parameters(), lr=a.lr, weight_decay=5e-4)
    ema = torch.optim.swa_utils.AveragedModel(model, avg_fn=lambda e, m, n: 0.995 * e + 0.005 * m)
    loader = dict(num_workers=a.workers, persistent_workers=True, prefetch_factor=4) if a.workers else {}
    batches = iter(torch.utils.data.DataLoader(Crops(samples, a.crop, a.batch, 0), batch_size=None, **loader))
    t0 = time.time()
    budget = a.minutes * 60
    step = 0
    while time.time() - t0 < budget:
        frac = (time.time() - t0) / budget
        for g in opt.param_groups:
            g["lr"] = a.lr * (0.05 + 0.95 * 0.5 * (1 + math.cos(math.pi * frac))) * min(1.0, (step + 1) / 100)
        imgs, targets = next(batches)
        model.train()
        loss, npos = loss_fn(model(imgs.to(dev, non_blocking=True)), targets)
        opt.zero_grad()
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 10.0)
        opt.step()
        ema.update_parameters(model)
        step += 1
        if step % 100 == 0:
            print(f"step {step} {time.time() - t0:.0f} s loss {loss.item():.3f} pos {npos}", flush=True)
        if step % 1000 == 0:
            save_state(ema.module, os.path.join(a.work, "ema.npz"))
    t_train = time.time() - t0
    if step:
        net = ema.module
        recalibrate_bn(net, batches, dev, n=max(60, 480 // a.batch))
    else:
        net = model.eval()
    net = net.cpu()
    save_state(net, os.path.join(a.work, "ema.npz"))
    summary = dict(params=params, imgsz=a.imgsz, crop=a.crop, batch=a.batch, steps=step,
                   train_minutes=round(t_train / 60, 1), data_minutes=round(t_data / 60, 1),
                   train_seeds=[p["seed"] for p in train_plan], val_seeds=[p["seed"] for p in val_plan],
                   train_windows=len(samples), min_score=a.min_score, frames=a.frames, objects=a.objects)

    if a.no_export:  # validate with torch (the machine may have no OpenCV 4.6 to compare with)
        net.export = True

        def run_torch(img):
            with torch.no_grad():
                return net(to_tensor([img.astype(np.float32)]))[0].numpy()

        rows = evaluate(val, run_torch, a.imgsz, a.min_score)
        summary.update(validation=rows)
        json.dump(summary, open(os.path.join(a.work, "report.json"), "w"), indent=1)
        print(json.dumps(rows, indent=1))
        return 0

    os.makedirs(a.out, exist_ok=True)
    onnx_path = os.path.join(a.out, "seabed_objects.onnx")
    meta = {
        "names": "{" + ", ".join(f"{i}: '{n}'" for i, n in enumerate(CLASSES)) + "}",
        "stride": str(max(STRIDES)),
        "imgsz": f"[{a.imgsz}, {a.imgsz}]",
        "task": "detect",
        "seamap.class_sizes_m": json.dumps(CLASS_SIZES_M),
        "seamap.layer": "raw",
        "seamap.layout": "yolov8",
        "seamap.min_score": str(a.min_score),
        "seamap.train_seeds": ",".join(str(p["seed"]) for p in train_plan),
        "seamap.data_hash": data_hash,
    }
    export_onnx(net, onnx_path, a.imgsz, meta)
    with open(os.path.join(a.out, "seabed_objects.names"), "w") as f:
        f.write("\n".join(CLASSES) + "\n")
    size_mb = os.path.getsize(onnx_path) / 1e6
    assert size_mb <= 4, f"model is {size_mb:.1f} MB, over 4 MB"

    # The same OpenCV 4.6 as the C++ detector: loads, runs, matches torch.
    cvnet = cv2.dnn.readNetFromONNX(onnx_path)
    cvnet.setPreferableBackend(cv2.dnn.DNN_BACKEND_OPENCV)
    cvnet.setPreferableTarget(cv2.dnn.DNN_TARGET_CPU)
    net.export = True
    worst = 0.0
    check = [w[0] for w in val[0][0][:10]] if val else [samples[0][0]]
    for img in check:
        blob = cv2.dnn.blobFromImage(cv2.cvtColor(img, cv2.COLOR_RGB2BGR), 1 / 255.0, swapRB=True, crop=False)
        cvnet.setInput(blob)
        out_cv = cvnet.forward()
        with torch.no_grad():
            out_t = net(torch.from_numpy(blob)).numpy()
        worst = max(worst, float(np.abs(out_cv - out_t).max()))
    print(f"cv2.dnn vs torch: max difference {worst:.2e}, output {out_cv.shape}", flush=True)
    assert worst < 1e-3, "cv2.dnn does not match torch"

    def run_net(img):
        blob = cv2.dnn.blobFromImage(cv2.cvtColor(img, cv2.COLOR_RGB2BGR), 1 / 255.0, swapRB=True, crop=False)
        cvnet.setInput(blob)
        return cvnet.forward()[0]

    rows = evaluate(val, run_net, a.imgsz, a.min_score)
    report = dict(summary, onnx_mb=round(size_mb, 2), cv_max_diff=worst, validation=rows)
    json.dump(report, open(os.path.join(a.work, "report.json"), "w"), indent=1)
    write_card(report, a.out)
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    sys.exit(main())
