"""Image files in and out.

Arrays at every public boundary are float32 (H, W, C), row 0 at the top, linear values in [0, 1].
8-bit files hold sRGB-encoded colour (decoded on read, encoded on write) unless ``srgb=False``;
16-bit PNG, ``.npy`` and EXR hold linear values. Data images (depth maps, ids) are read with
``srgb=False`` so that their values are not transformed.

Writes are atomic: the file is written under a temporary name in the same folder, then renamed.
"""

from __future__ import annotations

import glob
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from .errors import InputError, OutputError
from .files import load_npy

__all__ = [
    "read_image",
    "read_png_text",
    "write_image",
    "srgb_to_linear",
    "linear_to_srgb",
    "atomic_output",
    "remove_partial_outputs",
    "check_output_path",
    "as_image",
    "write_video",
    "VideoWriter",
]

_PIL_FORMATS = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp"}


def srgb_to_linear(values: np.ndarray) -> np.ndarray:
    """Decode sRGB-encoded values in [0, 1] to linear (IEC 61966-2-1)."""
    v = np.asarray(values, dtype=np.float32)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def linear_to_srgb(values: np.ndarray) -> np.ndarray:
    """Encode linear values in [0, 1] to sRGB (IEC 61966-2-1); input is clipped to [0, 1]."""
    v = np.clip(np.asarray(values, dtype=np.float32), 0.0, 1.0)
    return np.where(v <= 0.0031308, v * 12.92, 1.055 * v ** (1 / 2.4) - 0.055).astype(np.float32)


def as_image(array: np.ndarray, name: str = "image") -> np.ndarray:
    """Return ``array`` as float32 (H, W, C); a 2-D array becomes one channel.

    Raises InputError for anything that is not a non-empty 2-D or 3-D array with 1-4 channels.
    """
    a = np.asarray(array)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[0] == 0 or a.shape[1] == 0 or not 1 <= a.shape[2] <= 4:
        raise InputError(f"{name}: expected an H×W or H×W×C array with 1-4 channels, got shape {a.shape}")
    return a.astype(np.float32, copy=False)


def read_image(path: str | os.PathLike, srgb: bool | None = None) -> np.ndarray:
    """Read an image file as float32 (H, W, C) with values in [0, 1] (``.npy`` and EXR: as stored).

    ``srgb``: decode sRGB to linear. ``None`` (default) decodes 8-bit files and leaves 16-bit and
    float files as they are; pass ``False`` to read data such as depth maps unchanged.
    Raises InputError naming the file when it is missing, unreadable or empty.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    ext = p.suffix.lower()
    try:
        if ext == ".npy":
            return as_image(load_npy(p, "image array"), str(p))
        if ext == ".exr":
            return as_image(_read_exr(p), str(p))
        if ext == ".png":
            _check_png_end(p)
        if ext == ".png" and _png_bit_depth(p) == 16:
            arr, bits = _read_png16(p), 16
        else:
            from PIL import Image, UnidentifiedImageError

            try:
                with Image.open(p) as im:
                    im.load()
                    arr, bits = _pil_to_array(im)
            except UnidentifiedImageError:
                raise InputError(f"{p}: not an image file pillow can read") from None
    except InputError:
        raise
    except (OSError, ValueError, SyntaxError) as exc:
        raise InputError(f"{p}: cannot read image ({exc})") from None
    img = as_image(arr.astype(np.float32) / float(2**bits - 1), str(p))
    if srgb is None:
        srgb = bits == 8
    if srgb:
        rgb = srgb_to_linear(img[..., :3])
        img = np.concatenate([rgb, img[..., 3:]], axis=2) if img.shape[2] > 3 else rgb
    return img


def _check_png_end(p: Path) -> None:
    """A PNG ends with its IEND chunk; without it the file was cut, and pillow would still decode
    whatever rows the data that is left holds."""
    with open(p, "rb") as fh:
        head = fh.read(24)
        fh.seek(max(p.stat().st_size - 12, 0))
        tail = fh.read(12)
    if head[:8] == b"\x89PNG\r\n\x1a\n" and tail[4:8] != b"IEND":
        size = f"{int.from_bytes(head[16:20], 'big')}×{int.from_bytes(head[20:24], 'big')}" if len(head) >= 24 else "?"
        raise InputError(
            f"{p}: the PNG header declares a {size} image but the file ends before its last "
            f"chunk (IEND) — is it cut short?"
        )


def _png_bit_depth(p: Path) -> int:
    """Bit depth from a PNG's IHDR chunk (pillow reads 16-bit colour PNGs as 8-bit)."""
    with open(p, "rb") as fh:
        head = fh.read(26)
    if len(head) < 26 or head[:8] != b"\x89PNG\r\n\x1a\n":
        raise InputError(f"{p}: not a PNG file (bad signature)")
    return head[24]


def _read_png16(p: Path) -> np.ndarray:
    import png  # pypng: pillow cannot read or write 16-bit colour PNG

    try:
        width, height, rows, info = png.Reader(filename=str(p)).asDirect()
        arr = np.vstack([np.asarray(r, dtype=np.uint16) for r in rows])
    except png.Error as exc:
        raise InputError(f"{p}: corrupt PNG ({exc})") from None
    return arr.reshape(height, width, info["planes"])


def _pil_to_array(im) -> tuple[np.ndarray, int]:
    """Pixels of a PIL image and their bit depth (8 or 16)."""
    if im.mode in ("I;16", "I;16B", "I;16L", "I"):
        arr = np.asarray(im, dtype=np.uint32)
        return np.clip(arr, 0, 65535), 16
    if im.mode == "F":
        raise InputError("floating-point TIFF is not supported: save as .npy or 16-bit PNG")
    if im.mode not in ("L", "LA", "RGB", "RGBA"):
        im = im.convert("RGBA" if "A" in im.getbands() else "RGB")
    return np.asarray(im), 8


#: the channels of an EXR image by the number of channels of the array (OpenEXR's names)
_EXR_LAYOUT = {1: ("Y",), 2: ("Y", "A"), 3: ("RGB",), 4: ("RGBA",)}


def _read_exr(p: Path) -> np.ndarray:
    """An OpenEXR file's RGB(A) or Y(A) channels, float32 (H, W, C), values as stored."""
    import OpenEXR

    try:
        with OpenEXR.File(str(p)) as f:
            channels = {name: np.asarray(c.pixels) for name, c in f.channels().items()}
    except Exception as exc:  # the binding raises plain exceptions for any bad file
        raise InputError(f"{p}: not an OpenEXR file OpenEXR can read ({' '.join(str(exc).split())[:120]})") from None
    for layout in ("RGBA", "RGB"):
        if layout in channels:
            return channels[layout].astype(np.float32)
    if "Y" in channels:
        planes = [channels["Y"]] + ([channels["A"]] if "A" in channels else [])
        return np.stack(planes, axis=-1).astype(np.float32)
    raise InputError(f"{p}: EXR without RGB or Y channels (it has {', '.join(sorted(channels)) or 'none'})")


def _write_exr(tmp: Path, img: np.ndarray, half: bool) -> None:
    import OpenEXR

    data = img.astype(np.float16 if half else np.float32)
    names = _EXR_LAYOUT[img.shape[2]]
    if len(names) == 1 and len(names[0]) > 1:  # RGB, RGBA: one interleaved array
        planes = {names[0]: data}
    else:
        planes = {name: data[..., k] for k, name in enumerate(names)}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, planes) as f:
        f.write(str(tmp))


def check_output_path(output: str | os.PathLike, inputs: Iterable[str | os.PathLike] = ()) -> Path:
    """Refuse an output path that names one of the inputs; return it as a Path."""
    out = Path(output)
    for inp in inputs:
        if inp is None:
            continue
        ip = Path(inp)
        if ip.exists() and out.exists() and os.path.samefile(out, ip):
            raise OutputError(f"{out}: output would overwrite the input {ip}; choose another output path")
        if out.resolve() == ip.resolve():
            raise OutputError(f"{out}: output would overwrite the input {ip}; choose another output path")
    if out.exists() and out.is_dir():
        raise OutputError(f"{out}: is a folder, expected a file path")
    return out


class atomic_output:
    """Context manager yielding a temporary path next to ``path``; renamed onto it on success.

    On an exception the temporary file is removed and ``path`` is left untouched.
    """

    def __init__(self, path: str | os.PathLike):
        self.path = Path(path)
        self.tmp: Path | None = None

    def __enter__(self) -> Path:
        parent = self.path.parent
        try:
            parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{self.path.stem}.tmp-", suffix=self.path.suffix, dir=parent)
        except OSError as exc:
            raise OutputError(f"{self.path}: cannot write here ({exc.strerror})") from None
        os.close(fd)
        self.tmp = Path(tmp)
        return self.tmp

    def __exit__(self, exc_type, exc, tb) -> bool:
        assert self.tmp is not None
        if exc_type is None:
            try:
                umask = os.umask(0)
                os.umask(umask)
                os.chmod(self.tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the usual file mode
                os.replace(self.tmp, self.path)
            except OSError as err:
                self.tmp.unlink(missing_ok=True)
                raise OutputError(f"{self.path}: cannot write ({err.strerror})") from None
        else:
            self.tmp.unlink(missing_ok=True)
        return False


def remove_partial_outputs(path: str | os.PathLike) -> int:
    """Remove the temporaries an :class:`atomic_output` for ``path`` left behind when its writer was
    killed (a batch worker lost mid-write); returns how many. ``path`` itself is not touched."""
    path = Path(path)
    removed = 0
    for tmp in path.parent.glob(f".{glob.escape(path.stem)}.tmp-*{glob.escape(path.suffix)}"):
        tmp.unlink(missing_ok=True)
        removed += 1
    return removed


def read_png_text(path: str | os.PathLike) -> dict[str, str]:
    """The text chunks (tEXt, iTXt) of a PNG file, {} for none or another format."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as im:
            return {str(k): str(v) for k, v in getattr(im, "text", {}).items()}
    except (OSError, UnidentifiedImageError):
        return {}


def write_image(
    path: str | os.PathLike,
    image: np.ndarray,
    bit_depth: int = 8,
    srgb: bool | None = None,
    text: dict[str, str] | None = None,
) -> Path:
    """Write ``image`` (float (H, W, C) or (H, W), row 0 at the top) atomically; return the path.

    ``.png``: 8-bit (sRGB-encoded unless ``srgb=False``) or 16-bit (linear unless ``srgb=True``);
    ``.jpg``, ``.bmp``, ``.tif``, ``.webp``: 8-bit, in that format (pillow); ``.npy``: float32 as is;
    ``.exr``: OpenEXR, linear and unclipped, 32-bit float (``bit_depth=16``: half). The extension is
    read without regard to case. Values are clipped to [0, 1] for integer formats. NaN is refused.
    ``text``: key → value written as text chunks of an 8-bit PNG (what made the image).
    """
    p = Path(path)
    img = as_image(image, "image to write")
    ext = p.suffix.lower()
    if ext == ".npy":
        with atomic_output(p) as tmp, open(tmp, "wb") as fh:
            np.save(fh, img)
        return p
    if np.isnan(img).any():
        raise OutputError(f"{p}: image holds NaN values; refusing to write it")
    if ext == ".exr":
        if np.isinf(img).any() and bit_depth != 16:
            raise OutputError(f"{p}: image holds infinite values; refusing to write it")
        with atomic_output(p) as tmp:
            _write_exr(tmp, img, half=bit_depth == 16)
        return p
    if ext not in _PIL_FORMATS:
        raise OutputError(f"{p}: unknown image format {ext!r}; use .png, .jpg, .bmp, .tif, .webp, .npy or .exr")
    if bit_depth not in (8, 16) or (bit_depth == 16 and ext != ".png"):
        raise OutputError(f"{p}: {bit_depth}-bit output is not available for {ext}")
    if srgb is None:
        srgb = bit_depth == 8
    if srgb:
        rgb = linear_to_srgb(img[..., :3])
        img = np.concatenate([rgb, np.clip(img[..., 3:], 0, 1)], axis=2) if img.shape[2] > 3 else rgb
    img = np.clip(img, 0.0, 1.0)
    if bit_depth == 16:
        return _write_png16(p, img)
    from PIL import Image

    q = np.round(img * 255).astype(np.uint8)
    pil = Image.fromarray(q[..., 0] if img.shape[2] == 1 else q)
    if ext in (".jpg", ".jpeg") and pil.mode in ("RGBA", "LA"):
        pil = pil.convert("RGB" if pil.mode == "RGBA" else "L")
    extra = {}
    if text and ext == ".png":
        from PIL.PngImagePlugin import PngInfo

        info = PngInfo()
        for key, value in text.items():
            info.add_text(str(key), str(value))
        extra["pnginfo"] = info
    with atomic_output(p) as tmp:
        pil.save(tmp, format=Image.registered_extensions()[ext], **extra)
    return p


def _write_png16(p: Path, img: np.ndarray) -> Path:
    """16-bit PNG through pypng (pillow cannot write 16-bit colour)."""
    import png

    h, w, c = img.shape
    q = np.round(img * 65535).astype(np.uint16)
    mode = {1: "L", 2: "LA", 3: "RGB", 4: "RGBA"}[c] + ";16"
    with atomic_output(p) as tmp:
        png.from_array(q.reshape(h, w * c), mode).save(str(tmp))
    return p


def _video_frame(image: np.ndarray) -> np.ndarray:
    return (np.clip(linear_to_srgb(as_image(image)[..., :3]), 0, 1) * 255 + 0.5).astype(np.uint8)


class VideoWriter:
    """Frames appended one at a time to an .mp4 (H.264) or a looping .gif, written to a temporary
    file and renamed onto ``path`` when the ``with`` block ends without an error (a long recording
    never holds every frame in memory)::

        with VideoWriter("walk.mp4", fps=30) as video:
            for image in frames:
                video.append(image)     # linear float (H, W, 3)
    """

    def __init__(self, path: str | os.PathLike, fps: float = 12):
        self.path = Path(path)
        self.fps = float(fps)
        self.suffix = self.path.suffix.lower()
        if self.suffix not in (".mp4", ".gif"):
            raise InputError(f"{self.path.name}: a video must end in .mp4 or .gif")
        if not self.fps > 0:
            raise InputError(f"frames per second must be positive, got {fps}")
        self.frames = 0
        self._atomic = atomic_output(self.path)
        self._gif: list[np.ndarray] = []
        self._writer = None

    def __enter__(self) -> VideoWriter:
        self._tmp = self._atomic.__enter__()
        if self.suffix == ".mp4":
            import imageio.v2 as iio2

            self._writer = iio2.get_writer(
                self._tmp, format="FFMPEG", fps=self.fps, codec="libx264", macro_block_size=1, quality=8
            )
        return self

    def append(self, image: np.ndarray) -> None:
        frame = _video_frame(image)
        if self._writer is not None:
            self._writer.append_data(frame)
        else:
            self._gif.append(frame)  # a GIF is written whole (they are short)
        self.frames += 1

    def __exit__(self, exc_type, exc, tb) -> bool:
        try:
            if self._writer is not None:
                self._writer.close()
            elif exc_type is None:
                import imageio.v3 as iio

                iio.imwrite(self._tmp, np.stack(self._gif), extension=".gif", duration=1000 / self.fps, loop=0)
        finally:
            self._atomic.__exit__(exc_type, exc, tb)
        return False


def write_video(path: str | os.PathLike, images: list[np.ndarray], fps: float = 12) -> Path:
    """Write linear float frames (H, W, 3) as an .mp4 (H.264) or a looping .gif, atomically."""
    with VideoWriter(path, fps) as video:
        for image in images:
            video.append(image)
    return Path(path)
