#!/usr/bin/python3
"""CTest, in a build without a peer's library (cmake/CbpsPeers.cmake adds it only then): asking
for that peer exits 2 and says which Debian package to install, in `cbps lcp` and `cbps profile`
alike (the one refusal of src/solvers/peers/peers.cpp).

    /usr/bin/python3 tests/test_peer_not_built.py SOURCE_DIR CBPS PEER PACKAGE

Exit 0 when every check passes; each failed check is printed.
"""
import os
import subprocess
import sys


def main():
    source, cbps, peer, package = sys.argv[1:5]
    problem = os.path.join(source, "tests", "data", "siconos", "lcp", "lcp_CPS_1.dat")
    failures = 0
    r = subprocess.run([cbps, "lcp", problem, "--solver", peer], capture_output=True, text=True)
    for ok, what in ((r.returncode == 2, f"exit {r.returncode}, expected 2"),
                     ("this build has no" in r.stderr, "no 'this build has no' in stderr"),
                     (package in r.stderr, f"the package {package} not named"),
                     (r.stdout == "", "something on stdout")):
        if not ok:
            failures += 1
            print(f"FAILED: cbps lcp --solver {peer}: {what}\n{r.stderr}", file=sys.stderr)
    print(f"cbps lcp --solver {peer}: {r.stderr.strip()}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
