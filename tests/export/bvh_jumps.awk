# Prints how many times a BVH rotation channel moves by more than 180 degrees
# between consecutive frames (0 when every channel is continuous).
# Usage: awk -f bvh_jumps.awk FILE.bvh
/CHANNELS/ { for (i = 3; i <= NF; i++) rotation[n++] = ($i ~ /rotation/); next }
/^Frame Time/ { motion = 1; next }
motion {
  for (i = 1; i <= NF; i++) {
    if (have && rotation[i - 1]) { d = $i - previous[i]; if (d > 180 || d < -180) jumps++ }
    previous[i] = $i
  }
  have = 1
}
END { print jumps + 0 }
