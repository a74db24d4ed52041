"""Draws docs/images/photo_guide.png: how the six face photos of a cube are named and turned.

    python3 docs/tools/photo_guide.py SAMPLE_DIR docs/images/photo_guide.png

SAMPLE_DIR is any sample folder (e.g. `xylem sample --preset chestnut --size 256 --out S`);
its photos are laid out as the unfolded cross of docs/DESIGN.md (B above A, C A E F in the
middle row, D below A) and annotated with the face names and the cube axes. Needs Pillow.
"""
import sys
from PIL import Image, ImageDraw, ImageFont

T = 200  # tile side
GAP = 6
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf"
SMALL = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

# (column, row) of each face in the cross, and the words under its letter.
LAYOUT = {
    "B": (1, 0, "top, end grain\n(A's edge at the bottom)"),
    "C": (0, 1, "left side"),
    "A": (1, 1, "front"),
    "E": (2, 1, "right side"),
    "F": (3, 1, "back"),
    "D": (1, 2, "bottom, end grain\n(A's edge at the top)"),
}


def main(sample, out):
    margin = 60
    w = 4 * T + 3 * GAP + 2 * margin
    h = 3 * T + 2 * GAP + margin + 80
    img = Image.new("RGB", (w, h), "white")
    draw = ImageDraw.Draw(img)
    big = ImageFont.truetype(FONT, 44)
    small = ImageFont.truetype(SMALL, 15)
    for face, (c, r, words) in LAYOUT.items():
        photo = Image.open(f"{sample}/{face}_col.png").convert("RGB").resize((T, T))
        x, y = margin + c * (T + GAP), margin + r * (T + GAP)
        img.paste(photo, (x, y))
        draw.rectangle([x + T / 2 - 34, y + T / 2 - 44, x + T / 2 + 34, y + T / 2 + 14], fill="white")
        draw.text((x + T / 2, y + T / 2 - 15), face, fill="black", font=big, anchor="mm")
        draw.multiline_text((x + T / 2, y + T / 2 + 40), words, fill="white", font=small,
                            anchor="ma", align="center", stroke_width=2, stroke_fill="black")
    # Axes of the cube frame, drawn beside the cross: y up along the pith, x right on A, z out of A.
    ox, oy = margin + 3 * (T + GAP) + 40, margin + 2 * (T + GAP) + 150
    arrows = [((70, 0), "+x"), ((0, -70), "+y (pith, grain)"), ((-40, 40), "+z (out of A)")]
    for (dx, dy), label in arrows:
        draw.line([ox, oy, ox + dx, oy + dy], fill="black", width=3)
        draw.ellipse([ox + dx - 4, oy + dy - 4, ox + dx + 4, oy + dy + 4], fill="black")
        draw.text((ox + dx + 6, oy + dy - 8), label, fill="black", font=small)
    note = ("Stand the cube with its grain vertical. Photograph A, E, F, C upright, turning the cube\n"
            "a quarter turn each time: each photo's right edge meets the next face. B from above and\n"
            "D from below, both turned so that their edge shared with A touches A in this cross.")
    draw.multiline_text((margin, margin + 3 * (T + GAP) + 10), note, fill="black", font=small)
    img.quantize(colors=192).save(out, optimize=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
