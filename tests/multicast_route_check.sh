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

probe() {  # a connected sender and a receiver joined on the system's choice: prints received / not received
    /usr/bin/python3 - <<'PY'
import socket, struct
group, port = "224.5.23.2", 10003
r = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
r.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
r.bind((group, port))
r.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
             struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0")))
r.settimeout(1.0)
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.connect((group, port))
s.send(b"VSSRef_Command")
try:
    r.recvfrom(100)
    print("received")
except socket.timeout:
    print("not received")
PY
}

ip route add 224.0.0.0/4 dev lo
without=$(probe)
ip route del 224.0.0.0/4 dev lo
ip route add 224.0.0.0/4 dev lo src 127.0.0.1
with=$(probe)
echo "connected sender to 224.5.23.2: route without src: $without; with src 127.0.0.1: $with"
[ "$with" = received ] || { echo "FAIL: the documented route does not deliver"; exit 1; }
[ "$without" = "not received" ] || { echo "FAIL: the route without src delivered too; the docs' reason is wrong"; exit 1; }

# vssim's FIRASim vision to 224.0.0.1:10002, heard by a receiver joined on the system's choice.
"$vssim" serve kickoff_3v3 --port 0 --firasim --firasim-port 0 --quit-after 5 >/dev/null 2>&1 &
server=$!
vision=$(/usr/bin/python3 - <<'PY'
import socket, struct
group, port = "224.0.0.1", 10002
r = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
r.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
r.bind((group, port))
r.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
             struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0")))
r.settimeout(4.0)
try:
    data, _ = r.recvfrom(65536)
    print("received %d bytes" % len(data))
except socket.timeout:
    print("not received")
PY
)
kill "$server" 2>/dev/null || true
wait "$server" 2>/dev/null || true
echo "vssim's vision to 224.0.0.1:10002: $vision"
case "$vision" in received*) ;; *) echo "FAIL: vssim's vision did not arrive"; exit 1 ;; esac
