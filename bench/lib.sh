# Sourced by the multi-process benchmarks: a private network namespace with multicast routed on
# its loopback, so no packet leaves the machine (as the integration tests' tests/integration/
# lib.sh does), and a scratch folder that goes, with every background job, when the script ends.

# bench_enter_netns "$@": re-runs the calling script, with its arguments, inside a new namespace.
bench_enter_netns() {
  if [[ ${ODONATA_IN_NETNS:-0} != 1 ]]; then
    export ODONATA_IN_NETNS=1
    exec unshare -n sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$0" "$@"' \
      bash "$0" "$@"
  fi
}

# bench_scratch: sets TMP to a new folder; at exit the script's background jobs are killed and
# the folder removed.
bench_scratch() {
  TMP=$(mktemp -d)
  trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$TMP"' EXIT
}
