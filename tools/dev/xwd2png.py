#!/usr/bin/python3
"""Converts an Xvfb -fbdir screen file (XWD, 24/32 bpp ZPixmap) to PNG."""
import struct, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.image as mpimg
data = open(sys.argv[1], "rb").read()
fields = struct.unpack(">25I", data[:100])
header_size, version, fmt, depth, width, height = fields[:6]
byte_order, bpp, bytes_per_line, ncolors = fields[7], fields[11], fields[12], fields[19]
offset = header_size + ncolors * 12
pixels = np.frombuffer(data, dtype=np.uint8, count=bytes_per_line * height, offset=offset)
pixels = pixels.reshape(height, bytes_per_line)[:, : width * 4].reshape(height, width, 4)
# LSBFirst 32 bpp: B, G, R, X
rgb = pixels[:, :, [2, 1, 0]] if byte_order == 0 else pixels[:, :, [1, 2, 3]]
x0, y0, x1, y1 = [int(v) for v in sys.argv[3].split(",")] if len(sys.argv) > 3 else (0, 0, width, height)
mpimg.imsave(sys.argv[2], np.ascontiguousarray(rgb[y0:y1, x0:x1]))
