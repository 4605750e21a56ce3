#!/usr/bin/env bash
# The README's quick start on a fresh Debian 12, timed: a debootstrap minbase with only g++,
# cmake and git added (and what an installed system has that debootstrap does not write: the
# -updates and -security sources, /etc/hosts), a fresh clone of this repository's HEAD, then
# one of the two commands, whole.
#
#   sudo tests/bench/fresh_debian.sh quickstart|test [WORK_DIR]
#
# Needs root, debootstrap and Debian's mirror. WORK_DIR (default /tmp/redpost-fresh) gets the
# system (about 0.5 GB, 2.5 GB after the test command); it is replaced on every run. The
# evaluation data beside the repository (../shared) is bound into the system for the test
# command. Prints "fresh-debian: COMMAND exit E in S s". Not part of the suite.
set -euo pipefail
case ${1:-} in
  quickstart) command=scripts/quickstart.sh ;;
  test) command=scripts/test.sh ;;
  *)
    echo "usage: $0 quickstart|test [WORK_DIR]" >&2
    exit 2
    ;;
esac
[[ $(id -u) -eq 0 ]] || {
  echo "fresh-debian: needs root (debootstrap, chroot, mounts)" >&2
  exit 2
}
command -v debootstrap > /dev/null || {
  echo "fresh-debian: needs debootstrap (apt-get install debootstrap)" >&2
  exit 2
}
repo=$(cd "$(dirname "$0")/../.." && pwd)
root=${2:-/tmp/redpost-fresh}

mounts=(root/shared dev/shm dev/pts dev sys proc)
unmount_all() {
  for m in "${mounts[@]}"; do umount -l "$root/$m" 2> /dev/null || true; done
}
unmount_all
trap unmount_all EXIT
# --one-file-system: never into a mount that a lazy unmount left behind.
rm -rf --one-file-system "$root"
debootstrap --variant=minbase --include=ca-certificates,git,g++,cmake,make bookworm "$root" \
  http://deb.debian.org/debian > "$root.debootstrap.log" 2>&1
cp /etc/resolv.conf "$root/etc/resolv.conf"
printf '127.0.0.1 localhost\n::1 localhost\n' > "$root/etc/hosts"
rm -f "$root/etc/apt/sources.list"
cat > "$root/etc/apt/sources.list.d/debian.sources" << 'EOF'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
mount --bind /dev/shm "$root/dev/shm"
mount --bind /sys "$root/sys"
git clone -q "$repo" "$root/root/redpost"
mkdir -p "$root/root/shared"
if [[ -d $repo/../shared ]]; then mount --bind "$repo/../shared" "$root/root/shared"; fi

start=$(date +%s%N)
set +e
chroot "$root" /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  HOME=/root LANG=C.UTF-8 bash -c "cd /root/redpost && $command"
status=$?
set -e
end=$(date +%s%N)
echo "fresh-debian: $command exit $status in $(((end - start) / 1000000000)) s"
exit $status
