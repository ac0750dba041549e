#!/usr/bin/env bash
# The part of multicast_route_test.sh that runs inside its network namespace.
set -euo pipefail
vssim=$1
ip link set lo up
ip link add veth0 type veth peer name veth1
ip addr add 198.18.0.1/24 dev veth0
ip link set veth0 up
ip link set veth1 up
ip route add default via 198.18.0.2 dev veth0

# listen GROUP PORT SECONDS [send]: joins GROUP on the system's choice of
# interface, as team software does; with `send`, a socket connected to the
# group (as VSSReferee's command socket is) sends it one datagram. Prints
# "received N bytes" or "not received".
listen() {
    /usr/bin/python3 - "$@" <<'PY'
import socket, struct, sys
group, port, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
r = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
r.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
r.bind((group, port))
r.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
             struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0")))
r.settimeout(seconds)
if sys.argv[4:] == ["send"]:
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.connect((group, port))
    s.send(b"VSSRef_Command")
try:
    data, _ = r.recvfrom(65536)
    print("received %d bytes" % len(data))
except socket.timeout:
    print("not received")
PY
}

ip route add 224.0.0.0/4 dev lo
without=$(listen 224.5.23.2 10003 1 send)
ip route del 224.0.0.0/4 dev lo
ip route add 224.0.0.0/4 dev lo src 127.0.0.1
with=$(listen 224.5.23.2 10003 1 send)
echo "connected sender to 224.5.23.2: route without src: $without; with src 127.0.0.1: $with"
case "$with" in received*) ;; *) echo "FAIL: the documented route does not deliver"; exit 1 ;; esac
[ "$without" = "not received" ] || { echo "FAIL: the route without src delivered too; the docs' reason is wrong"; exit 1; }

# vssim's FIRASim vision to 224.0.0.1:10002, heard the same way.
"$vssim" serve kickoff_3v3 --port 0 --firasim --firasim-port 0 --quit-after 5 >/dev/null 2>&1 &
server=$!
vision=$(listen 224.0.0.1 10002 4)
kill "$server" 2>/dev/null || true
wait "$server" 2>/dev/null || true
echo "vssim's vision to 224.0.0.1:10002: $vision"
case "$vision" in received*) ;; *) echo "FAIL: vssim's vision did not arrive"; exit 1 ;; esac
