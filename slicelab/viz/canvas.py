"""Figures composed as pixel arrays (numpy and OpenCV), for previews that must cost little.

A `Canvas` is a white RGB image of bytes on which rendered panels are
pasted, with a frame and millimetre ticks around each, polygons filled and
outlined, and text; it is encoded as PNG by OpenCV. Nothing here imports
matplotlib, whose figure machinery costs a few tenths of a second per
picture.

See Also
--------
slicelab.viz.preview.save_split_preview : the split preview drawn this way.
"""
from __future__ import annotations

import numpy as np

__all__ = ["Canvas", "nice_ticks"]

_FONT_SCALE = 0.45
_SHIFT = 4  # fractional bits of the points handed to OpenCV's drawing functions


def nice_ticks(lo: float, hi: float, n: int = 6) -> np.ndarray:
    """Round tick values (1, 2 or 5 times a power of ten apart) within ``[lo, hi]``, about `n`.

    Examples
    --------
    >>> nice_ticks(-66.9, 66.9).tolist()
    [-60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0]
    """
    span = max(float(hi - lo), 1e-12)
    raw = span / max(n, 1)
    power = 10.0 ** np.floor(np.log10(raw))
    step = power * next(m for m in (1, 2, 5, 10) if span / (m * power) <= n + 1)
    first = np.ceil(lo / step) * step
    ticks = first + step * np.arange(int(np.floor((hi - first) / step + 1e-9)) + 1)
    return np.round(ticks, 10) + 0.0  # + 0.0 turns -0.0 into 0.0


def _label(v: float) -> str:
    return f"{v:g}"


class Canvas:
    """A white RGB picture of bytes, drawn into with OpenCV.

    Parameters
    ----------
    width, height : int
        Size in pixels.

    Attributes
    ----------
    rgb : (height, width, 3) uint8 ndarray

    Examples
    --------
    >>> c = Canvas(200, 100)
    >>> c.paste(np.zeros((10, 20, 4)), 5, 5)           # transparent: stays white
    >>> c.paste(np.ones((10, 20, 4)) * [1, 0, 0, 1], 50, 5)
    >>> c.paste(np.ones((10, 20, 4)) * [0, 0, 1, 0.5], 100, 5)  # half transparent
    >>> c.rgb[10, 10].tolist(), c.rgb[10, 60].tolist(), c.rgb[10, 110].tolist()
    ([255, 255, 255], [255, 0, 0], [127, 127, 255])
    >>> c.png()[:4]
    b'\\x89PNG'
    """

    def __init__(self, width: int, height: int):
        self.rgb = np.full((int(height), int(width), 3), 255, np.uint8)

    def paste(self, rgba, x: int, y: int) -> None:
        """Compose an RGBA image (floats in [0, 1] or bytes) over the canvas, top-left at (x, y)."""
        rgba = np.asarray(rgba)
        if rgba.dtype != np.uint8:
            rgba = np.rint(np.clip(rgba, 0, 1) * 255).astype(np.uint8)
        h, w = rgba.shape[:2]
        dst = self.rgb[y:y + h, x:x + w]
        a = rgba[..., 3]
        opaque = a == 255
        np.copyto(dst, rgba[..., :3], where=opaque[..., None])
        part = np.nonzero((a > 0) & ~opaque)  # pixels partly transparent (none in a depth rendering)
        if len(part[0]):
            alpha = a[part][:, None].astype(np.uint16)
            dst[part] = ((rgba[..., :3][part] * alpha + dst[part] * (255 - alpha) + 127) // 255).astype(np.uint8)

    def text(self, s: str, x: float, y: float, *, scale: float = 1.0, anchor: str = "left",
             colour=(0, 0, 0)) -> None:
        """Write `s` with its baseline at `y`; `anchor` ("left", "centre", "right") places it on `x`."""
        import cv2
        fs = _FONT_SCALE * scale
        (w, _), _ = cv2.getTextSize(s, cv2.FONT_HERSHEY_SIMPLEX, fs, 1)
        x0 = x - {"left": 0, "centre": w / 2, "right": w}[anchor]
        cv2.putText(self.rgb, s, (int(round(x0)), int(round(y))), cv2.FONT_HERSHEY_SIMPLEX, fs, colour, 1,
                    cv2.LINE_AA)

    def vtext(self, s: str, x: float, y: float, *, scale: float = 1.0) -> None:
        """Write `s` upwards (turned a quarter), centred on `y`, its baseline at `x`."""
        import cv2
        fs = _FONT_SCALE * scale
        (w, h), base = cv2.getTextSize(s, cv2.FONT_HERSHEY_SIMPLEX, fs, 1)
        strip = np.full((h + base + 2, w + 2, 3), 255, np.uint8)
        cv2.putText(strip, s, (1, h + 1), cv2.FONT_HERSHEY_SIMPLEX, fs, (0, 0, 0), 1, cv2.LINE_AA)
        turned = np.rot90(strip)
        top, left = int(round(y - turned.shape[0] / 2)), int(round(x - h - 1))
        region = self.rgb[top:top + turned.shape[0], left:left + turned.shape[1]]
        np.minimum(region, turned[:region.shape[0], :region.shape[1]], out=region)

    def axes(self, x: int, y: int, w: int, h: int, extent, *, xlabel: str = "", ylabel: str = "",
             title: str = "", ticks_left: bool = True) -> None:
        """Frame the panel at (x, y, w, h) showing `extent` = (s0, s1, t0, t1) mm, with ticks and labels."""
        import cv2
        s0, s1, t0, t1 = extent
        black = (0, 0, 0)
        cv2.rectangle(self.rgb, (x - 1, y - 1), (x + w, y + h), black, 1)
        for v in nice_ticks(s0, s1):  # ticks along the bottom, a handful
            px = x + (v - s0) / (s1 - s0) * w
            cv2.line(self.rgb, (int(round(px)), y + h), (int(round(px)), y + h + 4), black, 1)
            self.text(_label(v), px, y + h + 18, anchor="centre")
        for v in nice_ticks(t0, t1):  # ticks along the left side, a handful
            py = y + (t1 - v) / (t1 - t0) * h
            cv2.line(self.rgb, (x - 5, int(round(py))), (x - 1, int(round(py))), black, 1)
            if ticks_left:
                self.text(_label(v), x - 8, py + 5, anchor="right")
        if xlabel:
            self.text(xlabel, x + w / 2, y + h + 38, anchor="centre")
        if ylabel:
            self.vtext(ylabel, x - 42, y + h / 2)
        if title:
            self.text(title, x + w / 2, y - 10, scale=1.2, anchor="centre")

    def polygons(self, rings, *, colour, alpha: float = 0.0, width: int = 1) -> None:
        """Fill (with opacity `alpha`; even-odd rule) and outline rings of pixel coordinates (m, 2)."""
        import cv2
        pts = [np.rint(np.asarray(r, dtype=np.float64) * (1 << _SHIFT)).astype(np.int32).reshape(-1, 1, 2)
               for r in rings if len(r) >= 2]
        if not pts:
            return
        if alpha > 0:
            mask = np.zeros(self.rgb.shape[:2], np.uint8)
            cv2.fillPoly(mask, pts, 255, cv2.LINE_8, _SHIFT)
            ys, xs = np.nonzero(mask)
            self.rgb[ys, xs] = np.rint(self.rgb[ys, xs] * (1 - alpha) + np.asarray(colour) * alpha).astype(np.uint8)
        if width > 0:
            cv2.polylines(self.rgb, pts, True, colour, width, cv2.LINE_AA, _SHIFT)

    def lines(self, chains, *, colour, width: int = 1) -> None:
        """Open polylines of pixel coordinates (m, 2)."""
        import cv2
        pts = [np.rint(np.asarray(c, dtype=np.float64) * (1 << _SHIFT)).astype(np.int32).reshape(-1, 1, 2)
               for c in chains if len(c) >= 2]
        if pts:
            cv2.polylines(self.rgb, pts, False, colour, width, cv2.LINE_AA, _SHIFT)

    def png(self, level: int = 1) -> bytes:
        """The picture as PNG bytes (zlib `level`: 1 is fast and a little larger)."""
        import cv2
        ok, buf = cv2.imencode(".png", np.ascontiguousarray(self.rgb[..., ::-1]), [cv2.IMWRITE_PNG_COMPRESSION, level,
                                                                          cv2.IMWRITE_PNG_STRATEGY, cv2.IMWRITE_PNG_STRATEGY_RLE])
        if not ok:
            raise RuntimeError("OpenCV could not encode the picture as PNG")
        return buf.tobytes()
