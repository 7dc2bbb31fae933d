# Shared by scripts/demo.sh and scripts/view-bandwidth.sh (sourced, not run): what two processes
# on loopback need — a free block of UDP ports and stopping the remote site's process cleanly.

# free_udp_block FROM TO: the first base in FROM..TO (step 16) whose 16 ports all bind on
# 127.0.0.1 — camera i goes to base + 2 i, its RTCP to the next port, so a second run (or a test)
# beside this one does not collide. Prints nothing if there is none.
free_udp_block() {
  python3 - "$1" "$2" <<'PY'
import socket, sys
for base in range(int(sys.argv[1]), int(sys.argv[2]), 16):
    socks = []
    try:
        for p in range(base, base + 16):
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            socks.append(s)
            s.bind(("127.0.0.1", p))
    except OSError:
        continue
    finally:
        for s in socks:
            s.close()
    print(base)
    break
PY
}

# stop_remote: TERM the process in $remote_pid, KILL it after 5 s, reap it; clears remote_pid.
remote_pid=""
stop_remote() {
  if [ -n "$remote_pid" ] && kill -0 "$remote_pid" 2>/dev/null; then
    kill -TERM "$remote_pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$remote_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$remote_pid" 2>/dev/null || true
    wait "$remote_pid" 2>/dev/null || true
  fi
  remote_pid=""
}
