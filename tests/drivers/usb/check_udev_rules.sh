#!/bin/sh
# Every rule line in the station's udev rules (commented-out examples included: they get
# copied) must grant access through uaccess and 0660, never a world-writable mode.
set -eu
rules="$1"
[ -f "$rules" ] || { echo "FAIL: $rules not found"; exit 1; }
fail=0
n=0
# A rule line assigns MODE=; examples are rule lines behind a single '#'.
grep -n -E '^#?[A-Z].*MODE=' "$rules" > /tmp/hd_udev_rules.$$ || true
while IFS= read -r line; do
  n=$((n + 1))
  case "$line" in
    *'MODE="0666"'*|*"MODE=\"0777\""*|*'MODE="666"'*) echo "FAIL: world-writable: $line"; fail=1 ;;
  esac
  case "$line" in *'TAG+="uaccess"'*) ;; *) echo "FAIL: no TAG+=\"uaccess\": $line"; fail=1 ;; esac
  case "$line" in *'MODE="0660"'*) ;; *) echo "FAIL: mode is not 0660: $line"; fail=1 ;; esac
  case "$line" in *'GROUP="plugdev"'*) ;; *) echo "FAIL: no GROUP=\"plugdev\": $line"; fail=1 ;; esac
  case "$line" in
    *'SUBSYSTEM=="hidraw"'*)
      case "$line" in *'SYMLINK+="hybrid-tracker-'*) ;; *) echo "FAIL: hidraw rule without stable symlink: $line"; fail=1 ;; esac ;;
  esac
done < /tmp/hd_udev_rules.$$
rm -f /tmp/hd_udev_rules.$$
if grep -n -E 'MODE="?0?666' "$rules"; then echo "FAIL: 0666 anywhere"; fail=1; fi
[ "$n" -ge 2 ] || { echo "FAIL: expected at least 2 rules, found $n"; fail=1; }
[ "$fail" -eq 0 ] && echo "OK: $n rules in $rules, all 0660 + uaccess + plugdev"
exit "$fail"
