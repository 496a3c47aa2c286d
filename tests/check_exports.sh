#!/bin/sh
# check_exports.sh LIBRARY [SYMBOL_LIST]
# Fails when the shared library exports a defined symbol whose name does not start with dng_, and,
# given a list (tests/abi/libdngrid.symbols, one name a line, sorted), when its exported dng_ functions
# differ from that list: adding or removing a C function must be a deliberate edit of the list.
lib="$1"
list="$2"
others=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TtWwDdBbRrVviu]$/ && $3 !~ /^dng_/ && $3 !~ /^_(init|fini)$/ {print $3}')
if [ -n "$others" ]; then
  echo "$lib exports symbols outside the dng_ prefix:"
  echo "$others"
  exit 1
fi
count=$(nm -D --defined-only "$lib" | grep -c ' T dng_')
if [ -n "$list" ]; then
  exported=$(nm -D --defined-only "$lib" | awk '$2 == "T" && $3 ~ /^dng_/ {print $3}' | LC_ALL=C sort)
  if [ "$exported" != "$(cat "$list")" ]; then
    echo "$lib's exported functions differ from $list (< list, > library):"
    echo "$exported" | diff "$list" - || true
    exit 1
  fi
  echo "$lib exports exactly the $count functions of $list"
  exit 0
fi
echo "$lib exports $count dng_ functions and nothing else"
[ "$count" -gt 0 ]
