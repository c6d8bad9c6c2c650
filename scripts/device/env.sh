# Sourced by the device scripts: enter the bundle, unpack libglvnd, point the loader at the
# bundle's libraries and the NVIDIA driver, and let binaries built elsewhere find resources/.
set -u
bundle=${BUNDLE:-.gpu}
repo=$(pwd)
cd "$bundle" || { echo "no bundle folder $bundle" >&2; exit 1; }
mkdir -p /tmp/gl
for f in debs/*.deb; do dpkg -x "$f" /tmp/gl >/dev/null 2>&1; done
export LD_LIBRARY_PATH=$PWD/lib:/tmp/gl/usr/lib/x86_64-linux-gnu:/usr/local/nvidia/lib:/usr/local/nvidia/lib64
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
# fray-bench reads resources/ from the folder it was built in (FRAY_SOURCE_DIR).
for d in ${SOURCE_DIRS:-/work/main /work/wt-int}; do
  [ -e "$d" ] || { mkdir -p "$(dirname "$d")" && ln -s "$repo" "$d"; }
done
OUT=${OUT:-/tmp/device-out}
mkdir -p "$OUT"
