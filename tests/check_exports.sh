#!/bin/sh
# Fails when the shared library exports a defined symbol whose name does not start with dng_.
lib="$1"
others=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TtWwDdBbRrVviu]$/ && $3 !~ /^dng_/ && $3 !~ /^_(init|fini)$/ {print $3}')
if [ -n "$others" ]; then
  echo "$lib exports symbols outside the dng_ prefix:"
  echo "$others"
  exit 1
fi
count=$(nm -D --defined-only "$lib" | grep -c ' T dng_')
echo "$lib exports $count dng_ functions and nothing else"
[ "$count" -gt 0 ]
