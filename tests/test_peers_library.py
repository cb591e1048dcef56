#!/usr/bin/python3
"""CTest: the peers (siconos:NAME, bullet:NAME) on the quick problem library, judged here from
the problem files, independently of cbps.

    /usr/bin/python3 tests/test_peers_library.py SOURCE_DIR CBPS

Makes the quick library (scripts/make_problem_library.py CBPS TMP/lib --quick, 8 problems) and
runs `CBPS lcp PATH --solver PEER --json --iterations 100000` for every problem and peer, and
`--solver direct --tolerance 0` once per problem; the same on one folder with cfm.txt (a
two-box stack, `cbps matrices --cfm 1e-3`), whose problem is A + eps I. Checks:

  - a peer is refused (exit 2, a message naming the peer and why) exactly where this script's
    own reading of the problem says it must be: siconos:enum above 20 rows, bullet:lemke above
    1000, the others above 3000, siconos:avi with a free row, bullet:dantzig with a row whose
    box excludes 0;
  - otherwise exit 0 exactly when "status" is "solved" (src/cli/lcp.cpp: 0 solved, 1 not), the
    JSON object has every key of a `cbps lcp` result plus "peer" with its six keys, "scale" is
    max(1, |b|_inf, max |A_ij|) of the files, and the natural-map residual of the returned lambda,
    computed here in exact rational arithmetic from A, b, cmin, cmax as read by scipy (or the
    Siconos file as read by scripts/make_problem_library.py), is the reported one to cbps's own
    rounding, and the unit-free residual computed here likewise (include/cbps/system/
    unit_free.hpp) gives the same verdict (<= 1e-9, to the rounding of cbps's computation);
  - "peer.disagrees" is "peer said ok; unit-free residual R > 1e-09" exactly where the peer said
    ok and cbps says not solved (R the result's unit_free.relative), "peer said failed;
    unit-free residual ..." where it said failed and cbps says solved, null elsewhere;
  - where cbps says the peer solved the problem, the direct path's lambda agrees with the peer's
    to the bounds derived below from both residuals;
  - `cbps profile TMP/lib --quick` with peers among its solvers and `cbps converge` of a chain
    with peers write "final_point_only" true exactly for the peers and their "peer_status".

Prints a table of problem x peer -> cbps's status. Exit 0 when every check passes (each failed
check is printed), 77 with a SKIPPED line when this build has no Siconos or no Bullet.

The agreement bound. F(x) = A x - b (A = J Minv J^T + eps I, symmetric positive semidefinite),
K = [cmin, cmax], P the projection onto K. The natural-map residual of a point x is
r = x - P(x - F(x)). Take two points x1 (the peer's), x2 (the direct path's) with residuals
r1, r2, and put y_i = x_i - r_i = P(u_i), u_i = x_i - F(x_i), d = x1 - x2, e = r1 - r2.
P is firmly nonexpansive: <P(u1) - P(u2), u1 - u2> >= |P(u1) - P(u2)|^2 (add the two
projection inequalities <u_i - y_i, z - y_i> <= 0 at z = y_j). Here y1 - y2 = d - e and
u1 - u2 = d - A d, so <d - e, d - A d> >= |d - e|^2, which is

    d^T A d + |e|^2 <= <A d + d, e>                                               (1)

(the brief's d^T A d <= <A d + d, e>, with |e|^2 kept). (1) holds for any two points; computed
here in exact rational arithmetic it checks this script's own reading and arithmetic. Where A is
positive semidefinite (monotone F), d^T A d >= 0 and with B = max(0, <A d + d, e>):

    |A d|^2 = d^T A^2 d <= lambda_max(A) d^T A d <= lambda_max(A) B              (2)
    |J^T d|^2 <= m_max (J^T d)^T Minv (J^T d) <= m_max d^T A d <= m_max B        (3)

with m_max = 1 / lambda_min(Minv) (eps >= 0). So w1 - w2 = A d and the impulses J^T d agree to
sqrt(lambda_max B) and sqrt(m_max B) even where A is singular and lambda is not unique. The
stored A is J Minv J^T rounded: symmetric only to rounding (its two triangles round apart) and
with eigenvalues down to about -1e-14. So (2) is taken for S = (A + A^T) / 2 (d^T A d =
d^T S d), gains (lambda_max + mu) mu |d|^2 (mu >= -lambda_min(S); for each negative eigenvalue
lambda_k^2 <= lambda_max lambda_k + (lambda_max + mu) mu) and, as |A d| <= |S d| + |N|_F |d|
with N = (A - A^T) / 2, |N|_F |d| on |A d|; (3) takes (J^T d)^T Minv (J^T d) = d^T A d -
eps |d|^2 - d^T E d with E = A - J Minv J^T, computed exactly. The eigenvalue bounds are numpy's,
widened by 8 n u |S|_F (a backward-stable eigensolver).

(2) and (3) with B from the computed e hold for any two points too. What ties them to cbps's
verdicts is the same bounds with B_claim in place of B: when both residuals are at most
T_i (each lambda's natural-map residual as computed here, + its rounding), |e|_2 <= sqrt(n)
(T_1 + T_2) and by (1)
and Cauchy-Schwarz d^T A d <= |A d + d|_2 sqrt(n) (T_1 + T_2) = B_claim. Those checks use
nothing computed from the residual vectors: they fail when a lambda cbps called solved is not
a solution of the problem in the files (e.g. judged on a wrongly converted problem).
"""
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from fractions import Fraction

import numpy as np
import scipy.io
import scipy.sparse

PEERS = ("siconos:lemke", "siconos:pgs", "siconos:enum", "siconos:avi", "bullet:dantzig",
         "bullet:lemke", "bullet:pgs")
LCP_KEYS = ("problem", "rows", "cfm", "solver", "status", "iterations", "wall_time_s", "residual",
            "scale", "message", "space", "space_reason", "lambda")
PEER_KEYS = ("status", "said_ok", "iterations", "convert_time_s", "solve_time_s", "disagrees")
LCP_TIMEOUT_S = 30  # one `cbps lcp` of this script: under 2 s, sanitizers included
SOLVED = 1e-9  # `cbps lcp`'s "solved": unit-free residual <= 1e-9 (docs/cones.md, outputs.md)
U = 2.0 ** -53  # unit round-off
PROFILE_SOLVERS = ("pgs", "direct", "siconos:lemke", "siconos:pgs", "bullet:dantzig", "bullet:pgs")
CONVERGE_SOLVERS = ("pgs", "siconos:pgs", "bullet:dantzig")


def is_peer(solver):
    return solver.startswith("siconos:") or solver.startswith("bullet:")


def number(x):
    """A JSON number or cbps's "inf"/"-inf"/"nan" string as a float."""
    return float(x)


class Problem:
    """A, b, cmin, cmax (and J, Minv, eps) of a library entry, as floats and exactly."""

    def __init__(self, lib, entry, read_siconos):
        self.name = entry["name"]
        self.path = os.path.join(lib, entry["path"])
        self.J = self.Minv = None
        self.cfm = 0.0
        if entry["kind"] == "siconos":
            data = read_siconos(self.path)
            if data is None:
                raise RuntimeError(f"{self.path}: not a dense Siconos file")
            A, b, cmin, cmax = data
            self.A = scipy.sparse.csr_matrix(np.asarray(A, dtype=float))
        else:
            read = lambda name: scipy.io.mmread(os.path.join(self.path, name))
            vec = lambda name: np.asarray(read(name), dtype=float).reshape(-1)
            self.A = scipy.sparse.csr_matrix(read("A.mtx"))
            b, cmin, cmax = vec("b.mtx"), vec("cmin.mtx"), vec("cmax.mtx")
            cfm_file = os.path.join(self.path, "cfm.txt")
            if os.path.exists(cfm_file):
                self.cfm = float(open(cfm_file).read())
            if os.path.exists(os.path.join(self.path, "J.mtx")) and \
                    os.path.exists(os.path.join(self.path, "Minv.mtx")):
                self.J = scipy.sparse.csr_matrix(read("J.mtx"))
                self.Minv = scipy.sparse.csr_matrix(read("Minv.mtx"))
        self.b, self.cmin, self.cmax = (np.asarray(v, dtype=float) for v in (b, cmin, cmax))
        self.n = self.A.shape[0]
        # cbps's scale_of (include/cbps/system/boxed_problem.hpp) of A + eps I, formed here.
        Ae = (self.A + self.cfm * scipy.sparse.identity(self.n)).tocsr()
        self.dense = Ae.toarray()
        self.scale = max(1.0, float(np.max(np.abs(self.b), initial=0.0)),
                         float(np.max(np.abs(self.dense), initial=0.0)),
                         abs(self.cfm) if self.n else 0.0)
        # Exact copies: every double is a rational.
        coo = self.A.tocoo()
        self.A_exact = [(int(i), int(j), Fraction(float(a)))
                        for i, j, a in zip(coo.row, coo.col, coo.data)]
        self.b_exact = [Fraction(float(v)) for v in self.b]
        self.lo = [Fraction(float(v)) if math.isfinite(v) else None for v in self.cmin]
        self.hi = [Fraction(float(v)) if math.isfinite(v) else None for v in self.cmax]
        self.eps_exact = Fraction(self.cfm)
        # The rounding of cbps's own residual (w = A x + eps x - b, then two subtractions): a
        # row of k nonzeros costs at most gamma_{k+3} (|A| |x| + eps |x| + |b| + |x|).
        self.k = int(np.max(np.diff(self.A.indptr), initial=0)) + 1
        self.absA = abs(self.A)
        # A = J Minv J^T as computed is symmetric only to rounding (the two triangles round
        # apart): S = (A + A^T) / 2 carries the eigenvalue bounds, N = (A - A^T) / 2 (exact in
        # floating point, Sterbenz) is added to (2) as |N|_F |d|.
        S = (self.dense + self.dense.T) / 2
        self.asymmetry = float(np.linalg.norm((self.dense - self.dense.T) / 2)) * (1 + 1e-12)
        eig = np.linalg.eigvalsh(S) if self.n else np.zeros(1)
        widen = 8 * self.n * U * float(np.linalg.norm(S))
        self.lambda_max = max(float(eig[-1]), 0.0) + widen
        self.mu = max(0.0, -float(eig[0])) + widen
        self.m_max = None
        if self.J is not None:
            M = self.Minv.toarray()
            meig = np.linalg.eigvalsh((M + M.T) / 2)
            low = float(meig[0]) - 8 * M.shape[0] * U * float(np.linalg.norm(M))
            self.m_max = 1.0 / low if low > 0 else None
            coo = self.J.tocoo()
            self.J_exact = [(int(i), int(j), Fraction(float(a)))
                            for i, j, a in zip(coo.row, coo.col, coo.data)]
            coo = self.Minv.tocoo()
            self.Minv_exact = [(int(i), int(j), Fraction(float(a)))
                               for i, j, a in zip(coo.row, coo.col, coo.data)]

    def rounding(self, x):
        """An upper bound on the rounding of cbps's residual of x (floats), N."""
        x = np.abs(np.asarray(x, dtype=float))
        size = self.absA @ x + self.cfm * x + np.abs(self.b) + x
        return 4 * (self.k + 3) * U * float(np.max(size, initial=0.0))

    def unit_free(self, xe, Ax, x):
        """(relative, slack): the unit-free residual of include/cbps/system/unit_free.hpp at x,
        computed exactly from its definition (each row's natural map with step rho_k = 1/A_kk,
        the float cbps divides to, over max(|x|inf, max rho_k |b_k|)), and a bound on the
        rounding of cbps's float computation of it (rho_k times the residual's rounding)."""
        diagonal = self.dense.diagonal()
        top = float(np.max(diagonal, initial=0.0))
        fallback = 1.0 / top if top > 0.0 else 1.0
        rho = [1.0 / d if d > 0.0 else fallback for d in diagonal]
        largest = Fraction(0)
        for k in range(self.n):
            t = xe[k] - Fraction(rho[k]) * (Ax[k] - self.b_exact[k])
            if self.lo[k] is not None and t < self.lo[k]:
                t = self.lo[k]
            if self.hi[k] is not None and t > self.hi[k]:
                t = self.hi[k]
            largest = max(largest, abs(xe[k] - t))
        scale = max([abs(v) for v in xe] + [Fraction(rho[k]) * abs(self.b_exact[k])
                                            for k in range(self.n)] + [Fraction(0)])
        if scale == 0:
            return (0.0 if largest == 0 else math.inf), 0.0
        slack = max(rho + [0.0]) * self.rounding(x) / float(scale)
        return float(largest / scale), slack

    def residual(self, x):
        """(exact residual vector r, exact A x + eps x) of a finite float vector x."""
        xe = [Fraction(float(v)) for v in x]
        Ax = [Fraction(0)] * self.n
        for i, j, a in self.A_exact:
            Ax[i] += a * xe[j]
        Ax = [Ax[k] + self.eps_exact * xe[k] for k in range(self.n)]
        r = []
        for k in range(self.n):
            t = xe[k] - (Ax[k] - self.b_exact[k])
            if self.lo[k] is not None and t < self.lo[k]:
                t = self.lo[k]
            if self.hi[k] is not None and t > self.hi[k]:
                t = self.hi[k]
            r.append(xe[k] - t)
        return xe, r, Ax


def expected_refusal(peer, p):
    """Why this script expects cbps to refuse the peer on p (a word the message must hold), or
    None: the rules of docs and the brief, applied to the files as read here."""
    max_rows = {"siconos:enum": 20, "bullet:lemke": 1000}.get(peer, 3000)
    if p.n > max_rows:
        return f"at most {max_rows}"
    free = [k for k in range(p.n) if math.isinf(p.cmin[k]) and math.isinf(p.cmax[k])]
    if peer == "siconos:avi" and free:
        return "free"
    if peer == "bullet:dantzig" and any(not (p.cmin[k] <= 0.0 <= p.cmax[k]) for k in range(p.n)):
        return "cmin <= 0 <= cmax"
    return None


def norm_inf(v):
    return max((abs(x) for x in v), default=Fraction(0))


def sq(v):
    return sum((x * x for x in v), Fraction(0))


def dot(u, v):
    return sum((a * b for a, b in zip(u, v)), Fraction(0))


def agreement(p, peer_run, direct_run, check, where):
    """The bounds (1)-(3) of the docstring between the peer's and the direct path's lambda; the
    measured |A d|, |J^T d| and the claim-based bounds on them (for the report)."""
    (x1, r1, Ax1, t1), (x2, r2, Ax2, t2) = peer_run, direct_run
    n = p.n
    d = [a - b for a, b in zip(x1, x2)]
    e = [a - b for a, b in zip(r1, r2)]
    Ad = [a - b for a, b in zip(Ax1, Ax2)]  # (A + eps I) d, exactly
    dAd = dot(d, Ad)
    ee = sq(e)
    ip = dot([a + b for a, b in zip(Ad, d)], e)
    check(dAd + ee <= ip,
          f"{where}: (1) d^T A d + |e|^2 = {float(dAd + ee):.6g} > <A d + d, e> = {float(ip):.6g}")
    dd = sq(d)
    AdAd = sq(Ad)
    lam, mu = Fraction(p.lambda_max), Fraction(p.mu)
    extra_A = (lam + mu) * mu * dd
    B = max(Fraction(0), ip)
    # The claim: both residuals at most T1, T2 (+ rounding), so |e|_2 <= sqrt(n)(T1 + T2).
    Ad_plus_d = math.sqrt(float(sq([a + b for a, b in zip(Ad, d)])))
    B_claim = Fraction(Ad_plus_d * math.sqrt(n) * (t1 + t2) * (1 + 1e-12))
    check(dAd <= B_claim,
          f"{where}: d^T A d = {float(dAd):.6g} > |A d + d| sqrt(n) (T1 + T2) = "
          f"{float(B_claim):.6g}: a lambda called solved is not within its residual")
    # (2) for S = (A + A^T) / 2 (d^T A d = d^T S d), then |A d| <= |S d| + |N|_F |d|.
    asym = p.asymmetry * math.sqrt(float(dd))
    for name, bound in (("B", B), ("B_claim", B_claim)):
        limit = (math.sqrt(float(lam * bound + extra_A)) + asym) * (1 + 1e-12)
        check(math.sqrt(float(AdAd)) <= limit,
              f"{where}: (2) |w1 - w2| = |A d| = {math.sqrt(float(AdAd)):.6g} > "
              f"sqrt(lambda_max {name} + ...) + |N| |d| = {limit:.6g}")
    JdJd = None
    if p.J is not None:
        Jd = [Fraction(0)] * p.J.shape[1]
        for i, j, a in p.J_exact:
            Jd[j] += a * d[i]
        MJd = [Fraction(0)] * p.J.shape[1]
        for i, j, a in p.Minv_exact:
            MJd[i] += a * Jd[j]
        q = dot(Jd, MJd)  # (J^T d)^T Minv (J^T d)
        dEd = dAd - p.eps_exact * dd - q  # d^T (A - J Minv J^T) d, exactly
        JdJd = sq(Jd)
        check(p.m_max is not None, f"{where}: Minv is not positive definite")
        if p.m_max is not None:
            m = Fraction(p.m_max)
            for name, bound in (("B", B), ("B_claim", B_claim)):
                check(JdJd <= m * (bound + max(Fraction(0), -dEd)),
                      f"{where}: (3) |J^T d| = {math.sqrt(float(JdJd)):.6g} > "
                      f"sqrt(m_max {name} + ...) = "
                      f"{math.sqrt(float(m * (bound + max(Fraction(0), -dEd)))):.6g}")
    return {
        "w": math.sqrt(float(AdAd)),
        "w_bound": math.sqrt(float(lam * B_claim + extra_A)) + asym,
        "JTd": None if JdJd is None else math.sqrt(float(JdJd)),
        "JTd_bound": None if JdJd is None or p.m_max is None else math.sqrt(p.m_max * float(B_claim)),
    }


def run_lcp(cbps, path, solver, *extra):
    command = [cbps, "lcp", path, "--solver", solver, "--json", *extra]
    try:
        return subprocess.run(command, capture_output=True, text=True, timeout=LCP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        # A hang is named (the command and where it was) instead of ending in CTest's timeout.
        return subprocess.CompletedProcess(command, -1, "",
                                           f"did not end in {LCP_TIMEOUT_S} s: {' '.join(command)}")


def check_result_keys(j, solver, check, where):
    for key in LCP_KEYS:
        check(key in j, f"{where}: the JSON object has no \"{key}\"")
    check("peer" in j, f"{where}: the JSON object has no \"peer\"")
    if not is_peer(solver):
        check(j.get("peer", 0) is None, f"{where}: \"peer\" is {j.get('peer')!r}, not null")
        return
    peer = j.get("peer")
    check(isinstance(peer, dict), f"{where}: \"peer\" is {peer!r}, not an object")
    if not isinstance(peer, dict):
        return
    check(set(peer) == set(PEER_KEYS), f"{where}: peer keys {sorted(peer)}, not {sorted(PEER_KEYS)}")
    check(isinstance(peer.get("status"), str) and peer.get("status"),
          f"{where}: peer.status {peer.get('status')!r}")
    check(isinstance(peer.get("said_ok"), bool), f"{where}: peer.said_ok {peer.get('said_ok')!r}")
    it = peer.get("iterations")
    check(it is None or (isinstance(it, int) and not isinstance(it, bool) and it >= 0),
          f"{where}: peer.iterations {it!r}")
    for key in ("convert_time_s", "solve_time_s"):
        v = peer.get(key)
        check(isinstance(v, (int, float)) and not isinstance(v, bool) and v >= 0,
              f"{where}: peer.{key} {v!r}")
    check(j.get("solver") == solver, f"{where}: solver {j.get('solver')!r}")


def check_disagrees(j, check, where):
    """peer.disagrees against said_ok and cbps's verdict, with its two numbers."""
    peer = j["peer"]
    solved = j["status"] == "solved"
    text = peer.get("disagrees")
    if peer["said_ok"] and not solved:
        check(isinstance(text, str) and text.startswith("peer said ok; unit-free residual"),
              f"{where}: the peer said ok, cbps says {j['status']}, disagrees is {text!r}")
        m = re.fullmatch(r"peer said ok; unit-free residual (\S+) > (\S+)", text or "")
        check(m is not None, f"{where}: disagrees {text!r} is not 'peer said ok; unit-free "
                             "residual R > 1e-09'")
        if m:
            R, T = float(m.group(1)), float(m.group(2))
            uf = j["unit_free"]["relative"] if j.get("unit_free") else math.inf
            uf = math.inf if uf is None else uf
            check(math.isclose(R, uf, rel_tol=1e-5) or (math.isinf(R) and math.isinf(uf)),
                  f"{where}: disagrees says residual {R}, the result's unit-free {uf}")
            check(T == SOLVED, f"{where}: disagrees says T = {T}, the verdict's is {SOLVED}")
            check(R > T, f"{where}: disagrees says {R} > {T}")
    elif not peer["said_ok"] and solved:
        check(isinstance(text, str) and text.startswith("peer said failed; unit-free residual"),
              f"{where}: the peer said failed, cbps says solved, disagrees is {text!r}")
    else:
        check(text is None, f"{where}: peer said_ok {peer['said_ok']}, status {j['status']}, "
                            f"but disagrees is {text!r}")


def check_profile(cbps, lib, tmp, problems, check):
    out = os.path.join(tmp, "prof")
    r = subprocess.run([cbps, "profile", lib, "--quick", "--solvers", ",".join(PROFILE_SOLVERS),
                        "--time-limit", "0.5", "--quiet", "--no-plot", "--out", out],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"cbps profile exited {r.returncode}: {r.stderr.strip()}")
    if r.returncode != 0:
        return
    profile = json.load(open(os.path.join(out, "profile.json")))
    seen = {}
    for m in profile["measurements"]:
        key = (m["problem"], m["solver"])
        check(key not in seen, f"profile: {key} measured twice")
        seen[key] = m
    names = {p.name: p for p in problems}
    for name, p in names.items():
        for solver in PROFILE_SOLVERS:
            where = f"profile {name} x {solver}"
            m = seen.get((name, solver))
            check(m is not None, f"{where}: no measurement")
            if m is None:
                continue
            peer = is_peer(solver)
            refused = peer and expected_refusal(solver, p) is not None
            status = m.get("status", "")
            if refused:
                check(status.startswith("not applicable: "), f"{where}: status {status!r}")
                continue
            check(m.get("final_point_only") is peer,
                  f"{where}: final_point_only {m.get('final_point_only')!r}, expected {peer}")
            if not peer:
                check(m.get("peer_status") is None and m.get("convert_time_s") is None,
                      f"{where}: peer_status {m.get('peer_status')!r}, convert_time_s "
                      f"{m.get('convert_time_s')!r} for cbps's own method")
                continue
            ps = m.get("peer_status")
            check(isinstance(ps, str) and ps, f"{where}: peer_status {ps!r}")
            ct = m.get("convert_time_s")
            check(isinstance(ct, (int, float)) and 0 <= ct <= number(m["time_s"]),
                  f"{where}: convert_time_s {ct!r} not within time_s {m['time_s']}")
            rel = number(m["residual_relative"])  # unit-free (cbps profile)
            solved = rel <= 1e-10
            if solved:
                check(status == "solved", f"{where}: unit-free residual {rel:.3g}, status "
                                          f"{status!r}")
            elif ps.startswith("time limit"):
                # Killed at --time-limit (a Siconos child, or Bullet's, which runs in a child
                # under a limit): its status says so (slow builds, such as the sanitizers',
                # reach the 0.5 s limit on the base-3 pyramid).
                check(status == "time limit", f"{where}: peer_status {ps!r}, status {status!r}")
            else:
                check(status.startswith("peer said ok; unit-free residual ")
                      or status == f"peer said failed: {ps}",
                      f"{where}: unit-free residual {rel:.3g}, status {status!r} "
                      f"(peer_status {ps!r})")
    check(len(profile["measurements"]) == len(problems) * len(PROFILE_SOLVERS),
          f"profile: {len(profile['measurements'])} measurements, not "
          f"{len(problems)} x {len(PROFILE_SOLVERS)}")


def check_converge(cbps, chain, tmp, check):
    out = os.path.join(tmp, "conv")
    r = subprocess.run([cbps, "converge", chain, "--no-plot", "--quiet", "--solvers",
                        ",".join(CONVERGE_SOLVERS), "--out", out], capture_output=True, text=True)
    check(r.returncode == 0, f"cbps converge exited {r.returncode}: {r.stderr.strip()}")
    if r.returncode != 0:
        return
    summary = json.load(open(os.path.join(out, "summary.json")))
    by = {s["solver"]: s for s in summary["solvers"]}
    check(sorted(by) == sorted(CONVERGE_SOLVERS), f"converge: solvers {sorted(by)}")
    for solver, s in by.items():
        where = f"converge {solver}"
        if is_peer(solver):
            check(s.get("final_point_only") is True, f"{where}: final_point_only "
                                                     f"{s.get('final_point_only')!r}")
            check(isinstance(s.get("peer_status"), str) and s["peer_status"],
                  f"{where}: peer_status {s.get('peer_status')!r}")
            check(s.get("samples") == 2, f"{where}: {s.get('samples')} samples, not the guess "
                                         "and the final point")
            check(str(s.get("stopped", "")).startswith("final point only"),
                  f"{where}: stopped {s.get('stopped')!r}")
        else:
            check(s.get("final_point_only") is False and s.get("peer_status") is None,
                  f"{where}: final_point_only {s.get('final_point_only')!r}, peer_status "
                  f"{s.get('peer_status')!r} for cbps's own method")


def main():
    source, cbps = sys.argv[1], os.path.abspath(sys.argv[2])
    sys.path.insert(0, os.path.join(source, "scripts"))
    from make_problem_library import read_siconos  # scripts/make_problem_library.py

    started = time.monotonic()
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)
            print(f"FAILED: {what}", file=sys.stderr)

    with tempfile.TemporaryDirectory(prefix="cbps_peers_library_") as tmp:
        lib = os.path.join(tmp, "lib")
        r = subprocess.run([sys.executable, os.path.join(source, "scripts",
                                                          "make_problem_library.py"),
                            cbps, lib, "--quick"], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"FAILED: make_problem_library --quick exited {r.returncode}: {r.stderr}",
                  file=sys.stderr)
            return 1
        index = json.load(open(os.path.join(lib, "library.json")))
        library = [Problem(lib, e, read_siconos) for e in index["problems"]]
        check(len(library) == 8, f"{len(library)} quick problems, not 8")
        # One more, not in the library: a folder with cfm.txt (the peers get A + eps I, and
        # cbps's verdict and the residuals here are those of A + eps I).
        name = "stack-n2-step10-cfm0.001"
        r = subprocess.run([cbps, "matrices", "stack", "--param", "n=2", "--step", "10", "--cfm",
                            "1e-3", "--out", os.path.join(tmp, name)], capture_output=True,
                           text=True)
        check(r.returncode == 0, f"cbps matrices {name}: exit {r.returncode}: {r.stderr}")
        problems = library + ([Problem(tmp, {"name": name, "path": name, "kind": "matrices"},
                                       read_siconos)] if r.returncode == 0 else [])
        check(problems[-1].cfm == 1e-3 or r.returncode != 0, f"{name}: no cfm.txt of 1e-3")

        # A build without a peer library: skipped (both are optional, CBPS_PEERS).
        probe = next(p for p in problems if p.n <= 20 and expected_refusal("siconos:avi", p) is None
                     and expected_refusal("bullet:dantzig", p) is None)
        for peer in ("siconos:lemke", "bullet:pgs"):
            r = run_lcp(cbps, probe.path, peer)
            if r.returncode == 2 and "this build has no" in r.stderr:
                print(f"SKIPPED: {r.stderr.strip()}")
                return 77

        table = {}
        agreements = []
        chain = None
        for p in problems:
            if p.J is not None and chain is None and all(
                    math.isinf(a) and math.isinf(b) for a, b in zip(p.cmin, p.cmax)):
                chain = p.path
            if p.J is None:
                check(np.array_equal(p.dense, p.dense.T), f"{p.name}: A is not symmetric")
            else:
                # The folder's A is J Minv J^T to rounding (what (3) needs): entrywise within
                # twice the rounding of the product (k terms a row) and of A's own storage.
                JMJ = (p.J @ p.Minv @ p.J.T).toarray()
                size = (abs(p.J) @ abs(p.Minv) @ abs(p.J).T).toarray()
                k = int(np.max(np.diff(p.J.indptr))) * int(np.max(np.diff(p.Minv.indptr)))
                limit = 4 * (k + 2) * U * size + U * np.abs(JMJ)
                A = p.A.toarray()
                check(not (np.abs(A - JMJ) > limit).any(),
                      f"{p.name}: A.mtx is not J Minv J^T to rounding")
                check(not (np.abs(A - A.T) > 2 * limit).any(),
                      f"{p.name}: A.mtx is not symmetric to the rounding of J Minv J^T")
            where = f"{p.name} direct"
            r = run_lcp(cbps, p.path, "direct", "--tolerance", "0")
            check(r.returncode == 0, f"{where}: exit {r.returncode}: {r.stderr.strip()}")
            if r.returncode != 0:
                continue
            j = json.loads(r.stdout)
            check_result_keys(j, "direct", check, where)
            x2 = [number(v) for v in j["lambda"]]
            check(len(x2) == p.n and all(map(math.isfinite, x2)), f"{where}: lambda {j['lambda']}")
            xe2, r2, Ax2 = p.residual(x2)
            rho2 = p.rounding(x2)
            exact2 = float(norm_inf(r2))
            uf2, slack2 = p.unit_free(xe2, Ax2, x2)
            check(uf2 <= SOLVED + slack2,
                  f"{where}: unit-free residual {uf2:.6g} > 1e-9 (slack {slack2:.3g})")
            check(abs(number(j["residual"]) - exact2) <= rho2,
                  f"{where}: reported residual {j['residual']}, computed here {exact2:.17g}")
            direct = (xe2, r2, Ax2, exact2 + rho2)

            for peer in PEERS:
                where = f"{p.name} {peer}"
                r = run_lcp(cbps, p.path, peer, "--iterations", "100000")
                refusal = expected_refusal(peer, p)
                if r.returncode == 2:
                    message = r.stderr.strip()
                    table[(p.name, peer)] = "refused"
                    check(refusal is not None, f"{where}: refused unexpectedly: {message}")
                    check(message != "" and peer in message,
                          f"{where}: the refusal {message!r} does not name {peer}")
                    if refusal is not None:
                        check(refusal in message, f"{where}: the refusal {message!r} does not say "
                                                  f"\"{refusal}\"")
                    continue
                check(refusal is None, f"{where}: exit {r.returncode}, expected a refusal "
                                       f"({refusal})")
                check(r.returncode in (0, 1), f"{where}: exit {r.returncode}: {r.stderr.strip()}")
                try:
                    j = json.loads(r.stdout)
                except ValueError:
                    check(False, f"{where}: no JSON on stdout (exit {r.returncode}): "
                                 f"{r.stderr.strip()}")
                    continue
                check_result_keys(j, peer, check, where)
                if not isinstance(j.get("peer"), dict) or set(j["peer"]) != set(PEER_KEYS):
                    continue
                status = j["status"]
                table[(p.name, peer)] = status + ("*" if j["peer"]["disagrees"] else "") + (
                    " (abort)" if "ended the process" in j["peer"]["status"] else "")
                check((r.returncode == 0) == (status == "solved"),
                      f"{where}: exit {r.returncode} with status {status!r}")
                check(status in ("solved", "failed", "no_solution"), f"{where}: status {status!r}")
                check(j["rows"] == p.n, f"{where}: rows {j['rows']}, the files have {p.n}")
                check(j["scale"] == p.scale, f"{where}: scale {j['scale']!r}, max(1, |b|, |A|) of "
                                             f"the files is {p.scale!r}")
                check_disagrees(j, check, where)
                x1 = [number(v) for v in j["lambda"]]
                if len(x1) != p.n or not all(map(math.isfinite, x1)):
                    check(status != "solved", f"{where}: solved with lambda {j['lambda']}")
                    continue
                xe1, r1, Ax1 = p.residual(x1)
                rho1 = p.rounding(x1)
                exact1 = float(norm_inf(r1))
                reported = number(j["residual"])
                check(abs(reported - exact1) <= rho1,
                      f"{where}: reported residual {reported!r}, computed here {exact1:.17g} "
                      f"(rounding bound {rho1:.3g})")
                uf1, slack1 = p.unit_free(xe1, Ax1, x1)
                if status == "solved":
                    check(uf1 <= SOLVED + slack1,
                          f"{where}: cbps says solved, unit-free residual computed here "
                          f"{uf1:.6g} > 1e-9 (slack {slack1:.3g})")
                    stats = agreement(p, (xe1, r1, Ax1, exact1 + rho1), direct, check, where)
                    agreements.append((p.name, peer, stats))
                else:
                    check(uf1 > SOLVED - slack1,
                          f"{where}: cbps says {status}, unit-free residual computed here "
                          f"{uf1:.6g} <= 1e-9 (slack {slack1:.3g})")

        # The table: problem x peer -> cbps's status ("*": the peer's word disagrees).
        width = max(len(p.name) for p in problems)
        cols = [max(len(peer), 12) for peer in PEERS]
        print("problem".ljust(width) + "  " + "  ".join(s.ljust(c) for s, c in zip(PEERS, cols)))
        for p in problems:
            print(p.name.ljust(width) + "  " + "  ".join(
                table.get((p.name, peer), "-").ljust(c) for peer, c in zip(PEERS, cols)))
        print("(* the peer's own word disagrees with cbps's verdict: peer.disagrees)")
        print("\nagreement with the direct path where a peer solved (|w1 - w2|, |J^T d|, N, and "
              "their bounds from both residuals):")
        for name, peer, s in agreements:
            jt = "" if s["JTd"] is None else f"  |J^T d| {s['JTd']:.3g} <= {s['JTd_bound']:.3g}"
            print(f"  {name} {peer}: |A d| {s['w']:.3g} <= {s['w_bound']:.3g}{jt}")

        check(len(agreements) > 0, "no peer solved any problem: nothing compared")
        # The keys of every `cbps lcp` result were checked on every run above; the two the brief
        # names, on a folder with J and Minv, once more by name.
        check(("v-corner-step10", "siconos:lemke") in table
              and ("v-corner-step10", "bullet:dantzig") in table,
              "siconos:lemke and bullet:dantzig did not both run on v-corner-step10")

        check_profile(cbps, lib, tmp, library, check)
        check(chain is not None, "no chain (every row free) in the quick library")
        if chain is not None:
            check_converge(cbps, chain, tmp, check)
    print(f"\n{len(failures)} failed checks; {time.monotonic() - started:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
