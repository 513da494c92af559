#!/usr/bin/python3
"""A simulated survey's truth as a training-data folder in `seamap training-data`'s layout, as if an operator had
confirmed every object (a stand-in for the bench where `seamap training-data` and a review from the truth are
not available):

    scripts/truth_training_data.py SURVEY_DIR MAP.mbtiles OUT_DIR

Windows exactly as the recogniser composes them (scripts/train_detector.py survey_windows: levels base, base-2,
... 3 x 3 tiles), 768 px PNG, YOLO labels (objects at least 40 % inside the window), manifest.json with
classes (the simulator's), counts and windows."""
import json
import os
import sys

import cv2

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import train_detector as T  # noqa: E402

CLASSES = ["tyre", "crate", "pipe", "anchor", "rock", "drum"]  # core/sim/seabed_objects.cc, in id order


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    survey, mbtiles, out = sys.argv[1:]
    os.makedirs(os.path.join(out, "images"), exist_ok=True)
    os.makedirs(os.path.join(out, "labels"), exist_ok=True)
    T.CLASS_SIZES_M.setdefault("drum", [0.6, 0.9])
    windows, truth = T.survey_windows(survey, 768, mbtiles)
    mission = os.path.basename(os.path.normpath(survey))
    man = dict(classes=CLASSES, counts={c: 0 for c in CLASSES}, windows=[])
    for img, boxes, (z, x, y) in windows:
        name = f"{mission}_z{z}_x{x}_y{y}"
        cv2.imwrite(os.path.join(out, "images", name + ".png"), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
        labels = []
        # Each label's object (its index in the truth): the one whose box holds the label's centre, so an object
        # seen in several windows and levels is one object.
        holders = []
        for k, o in enumerate(truth["objects"]):
            pts = [T.lonlat_to_pixel(lon, lat, z) for lon, lat in o["footprint_lonlat"]]
            holders.append((k, o["class_id"], min(p[0] for p in pts) - x * 256, min(p[1] for p in pts) - y * 256,
                            max(p[0] for p in pts) - x * 256, max(p[1] for p in pts) - y * 256))
        with open(os.path.join(out, "labels", name + ".txt"), "w") as f:
            for c, x0, y0, x1, y1 in boxes:
                cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
                oid = next((str(k) for k, hc, a, b, a2, b2 in holders
                            if hc == int(c) and a <= cx <= a2 and b <= cy <= b2), "")
                f.write(f"{int(c)} {(x0 + x1) / 1536:.6f} {(y0 + y1) / 1536:.6f} {(x1 - x0) / 768:.6f} "
                        f"{(y1 - y0) / 768:.6f}\n")
                labels.append({"class": CLASSES[int(c)], "box_px": [float(x0), float(y0), float(x1), float(y1)],
                               "source": "truth", "id": oid})
                man["counts"][CLASSES[int(c)]] += 1
        man["windows"].append(dict(image=f"images/{name}.png", label=f"labels/{name}.txt", mission=mission, z=z,
                                   x=x, y=y, level=z, labels=labels, negatives=[]))
    json.dump(man, open(os.path.join(out, "manifest.json"), "w"), indent=1)
    print(f"{out}: {len(windows)} windows, labels {man['counts']}")


if __name__ == "__main__":
    main()
