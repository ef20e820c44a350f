#!/usr/bin/env bash
# common/sysid/'s rooms by role (common/sysid/CMakeLists.txt) keep their order: a room includes
# only itself and the rooms before it — model, estimation, selection, online — so the model
# never learns how it is estimated or chosen, and no include runs in a circle.
set -euo pipefail
SYSID=${1:?usage: check_sysid_rooms.sh SOURCE_DIR}/common/sysid
rooms=(model estimation selection online)
bad=0
for ((i = 0; i < ${#rooms[@]}; i++)); do
  room=${rooms[i]}
  [[ -d $SYSID/$room ]] || { echo "FAIL: no room $SYSID/$room"; exit 1; }
  for ((j = i + 1; j < ${#rooms[@]}; j++)); do
    later=${rooms[j]}
    if grep -n "#include \"sysid/$later/" "$SYSID/$room"/*; then
      echo "FAIL: $room includes $later (a later room) above"
      bad=1
    fi
  done
done
# Nothing left at the top: every file has its room.
if compgen -G "$SYSID/*.[ch]pp" >/dev/null; then
  echo "FAIL: files outside the rooms:" "$SYSID"/*.[ch]pp
  bad=1
fi
((bad == 0)) && echo "PASS: sysid rooms include only themselves and the rooms before them"
exit $bad
