#!/usr/bin/env bash
# docs/firasim.md's advice for multicast on one machine, checked in a network
# namespace of this test's own (nothing leaves it): a machine whose default
# route goes through another interface (a veth pair here), with
#     ip route add 224.0.0.0/4 dev lo src 127.0.0.1
# A socket connected to a group, as VSSReferee's command socket is, reaches a
# program that joined the group without naming an interface (as team
# software does), and so does vssim's FIRASim vision. Without `src` the
# connected socket takes the other interface's address and its datagram is
# not delivered: the test checks that too, so that it shows why `src` is there.
#
#   tests/multicast_route_test.sh VSSIM_BINARY
set -euo pipefail
vssim=${1:?usage: multicast_route_test.sh VSSIM_BINARY}
here=$(cd "$(dirname "$0")" && pwd)
# -r: root inside a user namespace of our own, so that no privilege is needed
# (as root it is not needed either, but does no harm).
exec unshare -rn bash "$here/multicast_route_check.sh" "$vssim"
