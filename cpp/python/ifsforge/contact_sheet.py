"""Contact sheets: thumbnails in a grid, each under an optional label (compare, the gallery)."""
import numpy as np

BACKGROUND = 0.06
LABEL_BACKGROUND = 0.15
LABEL_INK = 0.95


def thumbnail(image, cell):
    """RGB thumbnail at most cell x cell: k x k pooling, half mean and half max, so one-pixel
    curves stay visible; alpha is composited over the dark background."""
    image = np.asarray(image, np.float32)
    if image.ndim == 2:
        image = np.repeat(image[:, :, None], 3, axis=2)
    if image.shape[2] == 4:
        image = image[:, :, :3] * image[:, :, 3:4] + BACKGROUND * (1.0 - image[:, :, 3:4])
    k = max(1, -(-max(image.shape[:2]) // cell))
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    blocks = image[:h, :w, :3].reshape(h // k, k, w // k, k, 3)
    return 0.5 * blocks.mean(axis=(1, 3)) + 0.5 * blocks.max(axis=(1, 3))


def label(text, width, scale=2):
    """A dark strip `width` pixels wide with the lines of `text`, drawn with Pillow's built-in
    bitmap font enlarged `scale` times (nearest neighbour keeps it crisp)."""
    from PIL import Image, ImageDraw, ImageFont  # only sheets with labels need Pillow

    font = ImageFont.load_default()
    lines = text.split("\n")
    line_height = font.getbbox("Ag")[3] + 3
    small = Image.new("L", (max(1, width // scale), line_height * len(lines) + 2), 0)
    draw = ImageDraw.Draw(small)
    for n, line in enumerate(lines):
        draw.text((2, 1 + n * line_height), line, fill=255, font=font)
    big = small.resize((small.width * scale, small.height * scale), Image.NEAREST)
    ink = np.asarray(big, np.float32)[:, :width] / 255.0
    strip = np.full((ink.shape[0], width, 3), LABEL_BACKGROUND, np.float32)
    strip[:, :ink.shape[1]] += (LABEL_INK - LABEL_BACKGROUND) * ink[:, :, None]
    return strip


def contact_sheet(images, labels=None, columns=5, cell=256):
    """The images as thumbnails in `columns` columns, each under its label when labels are given."""
    strips = [label(text, cell) for text in labels] if labels else []
    label_height = max((s.shape[0] for s in strips), default=0)
    rows = (len(images) + columns - 1) // columns
    sheet = np.full((rows * (cell + label_height), columns * cell, 3), BACKGROUND, np.float32)
    for k, image in enumerate(images):
        r, c = divmod(k, columns)
        top, left = r * (cell + label_height), c * cell
        if strips:
            sheet[top:top + strips[k].shape[0], left:left + cell] = strips[k]
        thumb = thumbnail(image, cell)
        sheet[top + label_height:top + label_height + thumb.shape[0], left:left + thumb.shape[1]] = thumb
    return sheet
