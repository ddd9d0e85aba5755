# Sourced: `debian_source PACKAGE [--download-only]` fetches Debian 12's
# source package into the current folder with apt-get source, adding a
# deb-src line for bookworm when the system has none. Used by the
# manylinux build (scripts/manylinux) and scripts/prove-portable.sh.
debian_source() {
  if ! grep -rqsE "^(deb-src|Types:.*deb-src)" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    echo "debian-source: adding a deb-src line for bookworm (apt-get source)"
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm bookworm-updates\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      > /etc/apt/sources.list.d/paramorph-deb-src.sources
    apt-get update -qq
  fi
  if [ "${2:-}" != --download-only ] && ! command -v dpkg-source >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq dpkg-dev >/dev/null
  fi
  apt-get source -qq ${2:-} "$1" >/dev/null
}
