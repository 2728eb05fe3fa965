#!/usr/bin/python3
"""Measures how much of RViz's 3D view the tissue and the instrument cover.

Usage: rviz_screenshot_check.py VIEW_PPM MIN_TISSUE MIN_INSTRUMENT

VIEW_PPM is a binary 8-bit PPM of the 3D view alone (ImageMagick: import -window ID -depth 8).
A pixel is tissue when its colour is a shade of the tissue marker's (0.62, 0.22, 0.18)
(src/nodes/common/tissue_colour.h): the lighting scales the three channels alike, so G/R and B/R
stay near the marker's. It is instrument when it is a shade of the shaft's steel
(0.7, 0.7, 0.72, config/instruments/grasper.urdf): grey, not the grid's blue, brighter than
the background of config/training.rviz (20, 12, 12) and away from the view's most common colour
(the background, whichever it is). Prints both fractions of the view; exits 1 when one is
below its minimum.
"""
import collections
import sys

TISSUE = (0.62, 0.22, 0.18)
RATIO_TOLERANCE = 0.06
TISSUE_MIN_LEVEL = 40  # darker: too few levels for the ratios
STEEL_MIN_LEVEL = 40
BACKGROUND_MARGIN = 8


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval, separated by whitespace
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or fields[3] != b"255":
        sys.exit(f"{path}: not an 8-bit binary PPM")
    width, height = int(fields[1]), int(fields[2])
    return width * height, data[pos + 1:pos + 1 + 3 * width * height]


def main():
    path, min_tissue, min_instrument = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    count, rgb = read_ppm(path)
    g_ratio, b_ratio = TISSUE[1] / TISSUE[0], TISSUE[2] / TISSUE[0]
    colours = collections.Counter(rgb[i:i + 3] for i in range(0, len(rgb), 3))
    background = colours.most_common(1)[0][0]
    tissue = instrument = 0
    for r, g, b in zip(rgb[0::3], rgb[1::3], rgb[2::3]):
        if r >= TISSUE_MIN_LEVEL and abs(g / r - g_ratio) < RATIO_TOLERANCE and \
                abs(b / r - b_ratio) < RATIO_TOLERANCE:
            tissue += 1
        elif r >= STEEL_MIN_LEVEL and abs(g - r) <= 4 and -2 <= b - r <= 8 and \
                abs(r - background[0]) > BACKGROUND_MARGIN:
            instrument += 1
    tissue_fraction, instrument_fraction = tissue / count, instrument / count
    print(f"3D view {count} px: tissue {tissue_fraction:.3f} (min {min_tissue}), "
          f"instrument {instrument_fraction:.4f} (min {min_instrument})")
    sys.exit(0 if tissue_fraction >= min_tissue and instrument_fraction >= min_instrument else 1)


if __name__ == "__main__":
    main()
