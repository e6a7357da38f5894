# Sourced by ./run: the Debian chroots in which `./run test` runs the suite
# again on the FreeCAD of another Debian release (trixie: FreeCAD 1.0, sid:
# FreeCAD 1.1). Needs root (debootstrap, mount, chroot).
#
# Each chroot lives in $ISOCAM_CHROOT_CACHE/<suite> (default
# /var/cache/isocam/chroots/<suite>), outside the clone, and is reused by
# later runs. A chroot counts as complete only when its stamp file exists,
# written after debootstrap, the apt set-up and the project's own package
# install (`./run deps` inside) have all succeeded; a chroot without the
# stamp, or one that cannot run /bin/true, is deleted and built again.
#
# The Debian mirror is the host's own (the first non-security `URIs:` of
# /etc/apt/sources.list.d/*.sources, else the first `deb` line of
# /etc/apt/sources.list), read at run time; ISOCAM_DEBIAN_MIRROR overrides.

CHROOT_CACHE=${ISOCAM_CHROOT_CACHE:-/var/cache/isocam/chroots}
CHROOT_STAMP=.isocam-chroot-complete
CHROOT_SRC=/isocam          # where the clone is bound inside the chroot

debian_mirror() {
  if [ -n "${ISOCAM_DEBIAN_MIRROR:-}" ]; then echo "$ISOCAM_DEBIAN_MIRROR"; return; fi
  local m=""
  if compgen -G "/etc/apt/sources.list.d/*.sources" >/dev/null; then
    m=$(sed -n 's/^URIs:[[:space:]]*//p' /etc/apt/sources.list.d/*.sources \
      | tr ' ' '\n' | grep -v -e security -e '^$' | head -n 1 || true)
  fi
  if [ -z "$m" ] && [ -f /etc/apt/sources.list ]; then
    m=$(awk '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) { print $i; exit } }' \
      /etc/apt/sources.list | grep -v security | head -n 1 || true)
  fi
  if [ -z "$m" ]; then
    echo "isocam: no Debian mirror in the host's apt sources; set ISOCAM_DEBIAN_MIRROR" >&2
    return 1
  fi
  echo "$m"
}

# The mount points under $1 that are mounted now, deepest first.
chroot_mounts() {
  local dir
  dir=$(readlink -f "$1")
  awk -v d="$dir" '$2 == d || index($2, d "/") == 1 { print $2 }' /proc/self/mounts | sort -r
}

chroot_unmount() {
  local m
  for m in $(chroot_mounts "$1"); do
    umount "$m" 2>/dev/null || umount -l "$m" || true
  done
}

chroot_mount() {
  local dir=$1
  mkdir -p "$dir/proc" "$dir/sys" "$dir/dev" "$dir$CHROOT_SRC"
  mount -t proc proc "$dir/proc"
  mount --bind /sys "$dir/sys"
  mount --bind /dev "$dir/dev"
  mount --bind /dev/pts "$dir/dev/pts"
  mount --bind "$ROOT" "$dir$CHROOT_SRC"
}

# Delete a chroot, but never while anything is still mounted inside it
# (rm would go down into /dev or into the clone).
chroot_delete() {
  local dir=$1
  chroot_unmount "$dir"
  if [ -n "$(chroot_mounts "$dir")" ]; then
    echo "isocam: $dir still has mounts, not deleting it" >&2
    return 1
  fi
  rm -rf --one-file-system "$dir"
}

# Run a command inside the chroot with a clean environment.
in_chroot() {
  local dir=$1; shift
  chroot "$dir" /usr/bin/env -i HOME=/root TERM=dumb LANG=C.UTF-8 \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "$@"
}

chroot_ok() {
  [ -f "$1/$CHROOT_STAMP" ] && chroot "$1" /bin/true 2>/dev/null
}

# Make sure $CHROOT_CACHE/<suite> is complete; build it if not. The caller
# has mounted nothing yet.
chroot_prepare() {
  local suite=$1 dir=$CHROOT_CACHE/$1 mirror
  if chroot_ok "$dir"; then return 0; fi
  if ! command -v debootstrap >/dev/null; then
    echo "isocam: installing debootstrap"
    apt-get update || return 1
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends debootstrap \
      || return 1
  fi
  mirror=$(debian_mirror) || return 1
  if [ -e "$dir" ]; then
    echo "isocam: chroot $dir is incomplete, building it again"
    chroot_delete "$dir"
  fi
  mkdir -p "$CHROOT_CACHE"
  echo "isocam: debootstrap $suite into $dir"
  local t0=$SECONDS
  if ! debootstrap --variant=minbase "$suite" "$dir" "$mirror"; then
    echo "isocam: debootstrap $suite failed (see above); the next run builds it again" >&2
    return 1
  fi
  printf 'deb %s %s main\n' "$mirror" "$suite" > "$dir/etc/apt/sources.list"
  # sid's Release file may be older than its Valid-Until; nothing to check
  # for a test chroot.
  printf 'Acquire::Check-Valid-Until "false";\nAPT::Install-Recommends "false";\n' \
    > "$dir/etc/apt/apt.conf.d/90isocam"
  # No daemons started by package scripts inside the chroot.
  printf '#!/bin/sh\nexit 101\n' > "$dir/usr/sbin/policy-rc.d"
  chmod 755 "$dir/usr/sbin/policy-rc.d"
  echo "isocam: debootstrap $suite took $((SECONDS - t0)) s"
}

# Sessions in one chroot run one at a time: each binds the clone at the
# same place, and chroot_unmount undoes every mount under the chroot.
# ISOCAM_CHROOT_LOCK names the lock file (default: <suite>.lock beside the
# chroots); the lock is held from before the mounts to after the unmount.
chroot_locked() {
  local suite=$1 lock; shift
  lock=${ISOCAM_CHROOT_LOCK:-$CHROOT_CACHE/$suite.lock}
  mkdir -p "$(dirname "$lock")"
  (
    flock 9
    "$@"
  ) 9>"$lock"
}

# Run a command inside the chroot of a suite, with the project's packages
# installed there by its own install step (`./run deps`). The mounts are
# undone on every way out.
chroot_run() {
  local suite=$1 dir=$CHROOT_CACHE/$1 status=0
  shift
  chroot_prepare "$suite" || return 1
  cp -L /etc/resolv.conf "$dir/etc/resolv.conf" 2>/dev/null || true
  trap 'chroot_unmount "'"$dir"'"' EXIT
  trap 'exit 130' INT TERM
  chroot_mount "$dir"
  local t0=$SECONDS
  in_chroot "$dir" "$CHROOT_SRC/run" deps || status=$?
  echo "isocam[$suite]: packages took $((SECONDS - t0)) s"
  if [ $status -eq 0 ] && [ ! -f "$dir/$CHROOT_STAMP" ]; then
    date -u +%FT%TZ > "$dir/$CHROOT_STAMP"
  fi
  if [ $status -eq 0 ]; then
    in_chroot "$dir" "$@" || status=$?
  fi
  chroot_unmount "$dir"
  trap - EXIT INT TERM
  return $status
}

# The whole suite in one chroot: build into build-<suite>/ of the clone,
# ctest (the sanitizer build runs once, on the host: it does not depend on
# FreeCAD).
chroot_test() {
  chroot_locked "$1" chroot_run "$1" ISOCAM_BUILD_DIR="$CHROOT_SRC/build-$1" \
    "$CHROOT_SRC/run" test-on host
}
