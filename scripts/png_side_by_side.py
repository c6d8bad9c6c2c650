# png_side_by_side.py OUT.png X Y W H IN1.png [IN2.png ...]: crops each PNG to the box (X, Y, W, H in pixels)
# and writes them side by side, 8 white pixels apart (docs/POSTURE.md's before/after images).
# Reads the PNGs through `convert FILE.png ppm:-`; writes the PNG with the standard library only.
import subprocess, sys, zlib, struct
def readppm(path):
    data = subprocess.run(["convert", path, "ppm:-"], capture_output=True, check=True).stdout
    parts = []; i = 0
    while len(parts) < 4:
        while data[i:i+1].isspace(): i += 1
        if data[i:i+1] == b'#':
            while data[i:i+1] != b'\n': i += 1
            continue
        j = i
        while not data[j:j+1].isspace(): j += 1
        parts.append(data[i:j]); i = j
    i += 1
    w, h = int(parts[1]), int(parts[2])
    return w, h, data[i:i+w*h*3]
out, x, y, W, H = sys.argv[1], *map(int, sys.argv[2:6])
ims = [readppm(p) for p in sys.argv[6:]]
gap = 8
total = W*len(ims) + gap*(len(ims)-1)
rows = []
for r in range(H):
    row = bytearray()
    for k, (w, h, px) in enumerate(ims):
        if k: row += b'\xff\xff\xff'*gap
        start = ((y+r)*w + x)*3
        row += px[start:start+W*3]
    rows.append(b'\x00' + bytes(row))
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t+d) & 0xffffffff)
png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', total, H, 8, 2, 0, 0, 0)) + chunk(b'IDAT', zlib.compress(b''.join(rows), 9)) + chunk(b'IEND', b'')
open(out, 'wb').write(png)
