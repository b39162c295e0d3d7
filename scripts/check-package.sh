#!/usr/bin/env bash
# Release check of the DEB on a fresh Debian 12: debootstraps a minimal bookworm into a temporary
# directory, installs the package there with apt (Depends only, no Recommends: the declared
# dependencies must suffice) and renders the demo from the installed files inside that chroot:
# at full size, then at the golden's size through each GL backend (EGL, OSMesa), compared with
# tests/golden/demo_256x192.png by the installed `tubecast compare` (tests/golden/README.md:
# at most 0.5 % of the pixels off by more than 2/255).
# Unlike the build and the tests this downloads (the Debian mirror: debootstrap and apt); it is
# not part of scripts/test.sh. Needs root and debootstrap (apt-get install debootstrap).
# Usage: scripts/check-package.sh [tubecast_<version>_amd64.deb]   (default: the one in the root)
#   MIRROR=http://deb.debian.org/debian  KEEP=1 keeps the chroot (its path is printed)
set -euo pipefail
cd "$(dirname "$0")/.."
deb=${1:-$(ls -t tubecast_*_amd64.deb 2>/dev/null | head -n 1)}
[ -f "$deb" ] || { echo "check-package: no DEB given and none in the repository root (scripts/package.sh)" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || { echo "check-package: needs root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap >/dev/null || { echo "check-package: needs debootstrap (apt-get install debootstrap)" >&2; exit 2; }
MIRROR=${MIRROR:-http://deb.debian.org/debian}

work=$(mktemp -d /tmp/tubecast-check-package.XXXXXX)
root=$work/root
cleanup() {
  for m in "$root/dev/pts" "$root/dev" "$root/proc"; do
    mountpoint -q "$m" && umount -l "$m"
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "check-package: chroot kept in $root"; else rm -rf "$work"; fi
}
trap cleanup EXIT

echo "check-package: debootstrap bookworm (minbase) into $root"
debootstrap --variant=minbase bookworm "$root" "$MIRROR" > "$work/debootstrap.log" 2>&1 || {
  tail -n 20 "$work/debootstrap.log" >&2; exit 1; }
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
cp /etc/resolv.conf "$root/etc/resolv.conf"
cp "$deb" "$root/tmp/"
cp tests/golden/demo_256x192.png "$root/tmp/"

in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root "$@"; }
in_root apt-get update -qq
echo "check-package: apt install ./$(basename "$deb") (no recommends)"
in_root sh -c "cd /tmp && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ./$(basename "$deb")" \
  > "$work/apt.log" 2>&1 || { tail -n 30 "$work/apt.log" >&2; exit 1; }
in_root tubecast --version
in_root sh -c 'mkdir -p /tmp/demo && cd /tmp/demo && tubecast render /usr/share/tubecast/configs/demo.json -o out'
in_root sh -c 'test -s /tmp/demo/out/demo.png && test -s /tmp/demo/out/demo.exr'
ls -l "$root/tmp/demo/out"
for backend in egl osmesa; do
  in_root sh -c "cd /tmp/demo && tubecast render /usr/share/tubecast/configs/demo.json -o $backend -q \
    --backend $backend --set image.width=256 --set image.height=192"
  report=$(in_root tubecast compare "/tmp/demo/$backend/demo.png" /tmp/demo_256x192.png --threshold 0.0098)
  over=$(awk '$1 == "pixels_over_threshold_percent" { print $2 }' <<<"$report")
  echo "check-package: $backend at 256x192: $over % of the pixels off the golden"
  awk -v p="$over" 'BEGIN { exit !(p != "" && p <= 0.5) }' || { echo "$report" >&2; exit 1; }
done
echo "check-package: PASS: $(basename "$deb") installs on a fresh Debian 12 and renders the demo"
