#!/bin/sh
# Package test: `cpack -G DEB` makes dentsim's Debian package, which holds what a lab PC needs, declares its dependencies, and runs from a scratch root with no source tree.
#
# Usage: package_test.sh BUILD_DIR CPACK
# Registered by tests/CMakeLists.txt (ctest -R Package). The package and the scratch root live in a
# temporary folder; of them only cpack's install_manifest.txt lands in the build tree, none in the
# source tree. Exit 77: skipped.
set -eu

if [ $# -ne 2 ]; then
  echo "package_test: usage: package_test.sh BUILD_DIR CPACK" >&2
  exit 2
fi
build=$(cd "$1" && pwd) cpack=$2
for tool in dpkg-deb dpkg-shlibdeps; do
  if ! command -v "$tool" >/dev/null; then
    echo "package_test: SKIP: $tool is not installed (scripts/install-deps.sh installs it)"
    exit 77
  fi
done

tmp=$(mktemp -d /tmp/dentsim-package.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() {
  echo "package_test: FAIL: $*"
  failures=$((failures + 1))
}

# ---- build the package from the build tree's install rules --------------------------------------
# -B keeps cpack's staging folder and the package out of the build tree.
if ! "$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/out" >"$tmp/cpack.log" 2>&1; then
  cat "$tmp/cpack.log"
  echo "package_test: FAIL: cpack -G DEB failed"
  exit 1
fi
set -- "$tmp"/out/dentsim_*.deb
if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  ls -l "$tmp/out"
  echo "package_test: FAIL: cpack made no single dentsim_*.deb"
  exit 1
fi
deb=$1
echo "package_test: built $(basename "$deb"), $(wc -c <"$deb") bytes"

# ---- its contents: one file of each kind a lab needs, and no test ---------------------------------
dpkg-deb -c "$deb" | awk '{ print $NF }' >"$tmp/contents"
echo "package_test: $(grep -cv '/$' "$tmp/contents") files"
for f in ./usr/bin/dentsim \
         ./usr/share/dentsim/teeth/molar_enamel.stl \
         ./usr/share/dentsim/tools/tools.json \
         ./usr/share/dentsim/presets/default.json \
         ./usr/share/dentsim/tasks/class1_cavity.json \
         ./usr/share/dentsim/tasks/ct_tooth_3.dvol \
         ./usr/share/man/man1/dentsim.1.gz \
         ./usr/lib/udev/rules.d/70-dentsim.rules; do
  grep -qx "$f" "$tmp/contents" || fail "the package lacks $f"
done
# The shaders are compiled into the binary (cmake/Shaders.cmake embeds their SPIR-V), so they are
# not files; `dentsim gpu` and the demo below run them. Nothing from tests/ may ship.
if grep -E '_tests$|fake_hd|gtest|/tests/' "$tmp/contents"; then fail "the package holds test files (above)"; fi

# ---- its control file: name, section, and the dependencies dpkg-shlibdeps found -------------------
depends=$(dpkg-deb -f "$deb" Depends)
echo "package_test: Depends: $depends"
[ "$(dpkg-deb -f "$deb" Package)" = dentsim ] || fail "the package is not named dentsim"
[ "$(dpkg-deb -f "$deb" Section)" = science ] || fail "the package's section is not science"
[ -n "$(dpkg-deb -f "$deb" Maintainer)" ] || fail "the package names no maintainer"
for dep in libc6 libvulkan1 libglfw3 vulkan-icd; do
  case "$depends" in
    *"$dep"*) ;;
    *) fail "Depends does not name $dep" ;;
  esac
done

# ---- the man page: a real page, with every command's help -----------------------------------------
dpkg-deb --fsys-tarfile "$deb" | tar -xOf - ./usr/share/man/man1/dentsim.1.gz | gzip -dc >"$tmp/dentsim.1" ||
  fail "the man page is not a gzip file"
grep -q '^\.TH DENTSIM 1 ' "$tmp/dentsim.1" || fail "the man page has no .TH header"
for section in 'dentsim demo' 'dentsim run' 'dentsim gpu' 'dentsim task new'; do
  grep -qx ".SS \"$section\"" "$tmp/dentsim.1" || fail "the man page has no section for $section"
done

# ---- installed into a scratch root, run from a folder outside any source tree --------------------
root=$tmp/root
mkdir -p "$root" "$tmp/work"
dpkg -x "$deb" "$root"
dentsim=$root/usr/bin/dentsim
cd "$tmp/work"

# The binary finds its data beside itself, in the scratch root, not in a source tree or /usr.
version=$("$dentsim" --version) || fail "dentsim --version failed"
echo "package_test: $version" | tr '\n' ' '
echo
printf '%s\n' "$version" | grep -qx "data: $root/usr/share/dentsim" ||
  fail "the extracted dentsim does not name $root/usr/share/dentsim as its data"
# The same binary alone, with no share/dentsim beside it, says it has only its built-in assets: the
# data folder comes from where the binary is, never from a fixed place.
mkdir -p "$tmp/bare/bin"
cp "$dentsim" "$tmp/bare/bin/"
"$tmp/bare/bin/dentsim" --version | grep -q '^data: none beside this binary' ||
  fail "a dentsim without share/dentsim beside it claims a data folder"

# The Vulkan device and the compute kernels' self-test (lavapipe where there is no GPU).
"$dentsim" gpu >"$tmp/gpu.log" 2>&1 || { cat "$tmp/gpu.log"; fail "dentsim gpu failed"; }

# The installed course's tasks are valid as the installed binary reads them (the CT task's tooth,
# ct_tooth_3.dvol, is read from beside it).
for task in class1_cavity ct_caries_removal; do
  "$dentsim" task check "$root/usr/share/dentsim/tasks/$task.json" >"$tmp/check.log" 2>&1 ||
    { cat "$tmp/check.log"; fail "task check of the installed $task.json failed"; }
done

# A short headless demo: the smallest molar, no mirror, no sound, and a preset that cuts fast and
# samples the bur coarsely (as the app tests' fast preset), so it ends in seconds, scored.
cat >fast.json <<'EOF'
{"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},"point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}}
EOF
if "$dentsim" demo --headless --level 6 --mirror none --no-sound --params fast.json --out demo >"$tmp/demo.log" 2>&1; then
  for f in session.dses final.dvol score.json score.png; do
    [ -s "demo/$f" ] || fail "the demo wrote no $f"
  done
  grep -q 'score' "$tmp/demo.log" || fail "the demo printed no score"
else
  cat "$tmp/demo.log"
  fail "dentsim demo --headless failed"
fi

if [ "$failures" -ne 0 ]; then
  echo "package_test: $failures check(s) failed"
  exit 1
fi
echo "package_test: the package holds dentsim, its data, man page and udev rules, and runs from $root"
