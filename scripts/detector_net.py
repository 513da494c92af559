"""The recogniser's network, a small anchor-free YOLO-style detector (three levels, strides 8/16/32, FCOS-style
centre sampling), and its training loss. Used by scripts/train_detector.py, which trains it and exports it to ONNX
for core/detect."""
import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F
import torchvision

STRIDES = (8, 16, 32)


class ConvBN(nn.Sequential):
    def __init__(self, cin, cout, k=3, s=1):
        super().__init__(nn.Conv2d(cin, cout, k, s, k // 2, bias=False), nn.BatchNorm2d(cout), nn.SiLU())


class Block(nn.Module):
    """CSP-style: half the channels through two 3x3 convs with a residual, concatenated, fused."""

    def __init__(self, c):
        super().__init__()
        h = c // 2
        self.a = ConvBN(c, h, 1)
        self.b = ConvBN(c, h, 1)
        self.m = nn.Sequential(ConvBN(h, h, 3), ConvBN(h, h, 3))
        self.out = ConvBN(2 * h, c, 1)

    def forward(self, x):
        a = self.a(x)
        return self.out(torch.cat([a + self.m(a), self.b(x)], 1))


class SPPF(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.cv1 = ConvBN(c, c // 2, 1)
        self.cv2 = ConvBN(c * 2, c, 1)
        self.pool = nn.MaxPool2d(5, 1, 2)

    def forward(self, x):
        x = self.cv1(x)
        y1 = self.pool(x)
        y2 = self.pool(y1)
        return self.cv2(torch.cat([x, y1, y2, self.pool(y2)], 1))


class Detector(nn.Module):
    def __init__(self, nc, w=(12, 24, 32, 48, 64)):
        super().__init__()
        self.nc = nc
        self.stem = nn.Sequential(ConvBN(3, w[0], 3, 2), ConvBN(w[0], w[1], 3, 2))
        self.p3 = nn.Sequential(ConvBN(w[1], w[2], 3, 2), Block(w[2]))
        self.p4 = nn.Sequential(ConvBN(w[2], w[3], 3, 2), Block(w[3]))
        self.p5 = nn.Sequential(ConvBN(w[3], w[4], 3, 2), Block(w[4]), SPPF(w[4]))
        self.lat5 = ConvBN(w[4], w[3], 1)
        self.td4 = Block(w[3])
        self.lat4 = ConvBN(w[3], w[2], 1)
        self.td3 = Block(w[2])
        self.down3 = ConvBN(w[2], w[2], 3, 2)
        self.pan4 = ConvBN(w[2] + w[3], w[3], 1)
        self.down4 = ConvBN(w[3], w[3], 3, 2)
        self.pan5 = ConvBN(w[3] + w[4], w[4], 1)
        self.heads = nn.ModuleList()
        for c in (w[2], w[3], w[4]):
            self.heads.append(nn.ModuleDict({
                "box": nn.Sequential(ConvBN(c, c, 3), nn.Conv2d(c, 4, 1)),
                "cls": nn.Sequential(ConvBN(c, c, 3), nn.Conv2d(c, nc, 1)),
            }))
        for h in self.heads:  # start with a low score everywhere (focal loss prior)
            nn.init.constant_(h["cls"][-1].bias, -4.6)
        self.export = False

    def features(self, x):
        c2 = self.stem(x)
        c3 = self.p3(c2)
        c4 = self.p4(c3)
        c5 = self.p5(c4)
        t4 = self.td4(c4 + F.interpolate(self.lat5(c5), scale_factor=2.0, mode="nearest"))
        t3 = self.td3(c3 + F.interpolate(self.lat4(t4), scale_factor=2.0, mode="nearest"))
        n4 = self.pan4(torch.cat([self.down3(t3), t4], 1))
        n5 = self.pan5(torch.cat([self.down4(n4), c5], 1))
        return [t3, n4, n5]

    def forward(self, x):
        return self.decode(self.features(x))

    def decode(self, feats):
        outs = []
        for f, h, s in zip(feats, self.heads, STRIDES):
            dist = F.softplus(h["box"](f)) * s  # l, t, r, b in input pixels
            logits = h["cls"](f)
            if not self.export:
                outs.append((dist, logits))
                continue
            # Decoded per level on 4-D tensors with a constant grid of the same shape (OpenCV 4.6).
            _, _, hh, ww = f.shape
            gx, gy = np.meshgrid((np.arange(ww, dtype=np.float32) + 0.5) * s, (np.arange(hh, dtype=np.float32) + 0.5) * s)
            grid = torch.from_numpy(np.stack([gx, gy])[None].copy())  # [1, 2, H, W] cell centres, a constant
            lt, rb = dist[:, 0:2], dist[:, 2:4]
            x1y1 = grid - lt
            x2y2 = grid + rb
            cxcy = (x1y1 + x2y2) * 0.5
            wh = x2y2 - x1y1
            y = torch.cat([cxcy, wh, torch.sigmoid(logits)], 1)  # [1, 4+C, H, W]
            outs.append(y.reshape(1, 4 + self.nc, hh * ww))
        return torch.cat(outs, 2) if self.export else outs


SIZE_RANGES = ((0, 48), (32, 96), (64, 1e9))  # box longest side (input px) per level


def loss_fn(outs, targets):
    """targets: list (batch) of [K, 5] (class, x1, y1, x2, y2); class -1 marks a region whose cells get no class
    loss (neither object nor background) unless positive for another box. Centre-sampled FCOS-style assignment: a
    cell is positive for the smallest box of its level's size range that holds it and whose centre is within 2.5
    strides. All images of the batch at once (one box list with image indices), so a step is a few dozen kernels."""
    dev = outs[0][0].device
    image = torch.cat([torch.full((len(t),), i, dtype=torch.long) for i, t in enumerate(targets)]).to(dev)
    boxes = torch.as_tensor(np.concatenate([np.asarray(t, np.float32).reshape(-1, 5) for t in targets]), device=dev)
    ignored = boxes[:, 0] < 0  # class -1: a region that is taught neither as an object nor as background
    ign, ign_image = boxes[ignored], image[ignored]
    boxes, image = boxes[~ignored], image[~ignored]
    cls_losses, box_losses, npos = 0.0, 0.0, 0
    for (dist, logits), s, (lo, hi) in zip(outs, STRIDES, SIZE_RANGES):
        b, nc, h, w = logits.shape
        gy, gx = torch.meshgrid((torch.arange(h, device=dev) + 0.5) * s, (torch.arange(w, device=dev) + 0.5) * s,
                                indexing="ij")
        cls_t = torch.zeros_like(logits)
        side = torch.maximum(boxes[:, 3] - boxes[:, 1], boxes[:, 4] - boxes[:, 2])
        keep = (side >= lo) & (side < hi)
        t, ti = boxes[keep], image[keep]
        k = len(t)
        if k:
            cx, cy = (t[:, 1] + t[:, 3]) / 2, (t[:, 2] + t[:, 4]) / 2
            area = (t[:, 3] - t[:, 1]) * (t[:, 4] - t[:, 2])
            X, Y = gx[None], gy[None]
            inside = (X > t[:, 1, None, None]) & (X < t[:, 3, None, None]) & (Y > t[:, 2, None, None]) & (
                Y < t[:, 4, None, None])
            r = 2.5 * s
            near = ((X - cx[:, None, None]).abs() < r) & ((Y - cy[:, None, None]).abs() < r)
            cost = torch.full((b, k, h, w), 1e12, device=dev)  # area of each candidate box, per image
            cost[ti, torch.arange(k, device=dev)] = torch.where(inside & near, area[:, None, None],
                                                                torch.full((k, h, w), 1e12, device=dev))
            smallest, best = cost.min(1)
            ii, yy, xx = torch.nonzero(smallest < 1e11, as_tuple=True)
            if len(ii):
                kk = best[ii, yy, xx]
                cls_t[ii, t[kk, 0].long(), yy, xx] = 1.0
                px, py = gx[yy, xx], gy[yy, xx]
                d = dist.permute(0, 2, 3, 1)[ii, yy, xx]  # [n, 4]
                pred = torch.stack([px - d[:, 0], py - d[:, 1], px + d[:, 2], py + d[:, 3]], 1)
                box = t[kk, 1:5]
                box_losses = box_losses + torchvision.ops.generalized_box_iou_loss(pred, box, reduction="sum") + \
                    0.5 * (F.l1_loss(pred, box, reduction="none").sum(1) / s).sum()
                npos += len(ii)
        if not len(ign):  # (no ignored region: the loss as it always was)
            cls_losses = cls_losses + torchvision.ops.sigmoid_focal_loss(logits, cls_t, alpha=0.25, gamma=2.0,
                                                                         reduction="sum")
            continue
        X, Y = gx[None], gy[None]
        in_ign = (X > ign[:, 1, None, None]) & (X < ign[:, 3, None, None]) & (Y > ign[:, 2, None, None]) & (
            Y < ign[:, 4, None, None])
        masked = torch.zeros((b, h, w), device=dev).index_add_(0, ign_image, in_ign.float()) > 0
        masked &= cls_t.amax(1) == 0  # a cell positive for a real box keeps its loss
        cls_losses = cls_losses + (torchvision.ops.sigmoid_focal_loss(logits, cls_t, alpha=0.25, gamma=2.0,
                                                                      reduction="none") * (~masked)[:, None]).sum()
    n = max(npos, 1)
    return (cls_losses + 2.0 * box_losses) / n, npos
