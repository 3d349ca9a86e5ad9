"""The compiled kernel of the dyad path (numba): one design variant over all crank angles, and the
drivers that run many variants in parallel threads or one serially.

Imported on first use by :mod:`mechdyn.mechanism.dyads.run` (numba is slow to import); compiled once
and cached on disk. It takes one :class:`~mechdyn.mechanism.dyads.arguments.KernelArgs`, whose
fields it reads by name; the operation codes are those of
:func:`mechdyn.mechanism.dyads.arguments.encode`.
"""

import numba
import numpy as np

__all__ = ["run_parallel", "run_serial"]


@numba.njit(cache=True, error_model="numpy")
def _cross(a, b):
    return a.real * b.imag - a.imag * b.real


@numba.njit(cache=True, error_model="numpy")
def _over(z, d):
    """z / d for a complex z and a real d, part by part: the value of the complex division (whose
    denominator has no imaginary part), without its general algorithm's branches."""
    return complex(z.real / d, z.imag / d)


@numba.njit(cache=True, error_model="numpy")
def variant(v, args, lane):
    # v: the variant (its inputs, its joint-force peaks); lane: the row of the per-angle outputs it
    # writes (v itself, or a row of the summary-only batch's work buffers)
    # the fields by the short names of the formulas below
    dz, ops, fdata, grounded = args.drawing, args.ops, args.op_data, args.grounded
    turn, omega, alpha = args.turn, args.omega, args.alpha
    vw = np.int64(v) if omega.shape[0] > 1 else np.int64(0)  # one row of rates: every variant
    mass, inertia, grav = args.mass, args.inertia, args.gravity
    keep, out_slot, u_out = args.keep, args.output_slot, args.output_axis
    pos_out, vel_out, acc_out, rate_out = args.pos, args.vel, args.acc, args.rates
    force, inertia_force, moment, torque = args.force, args.inertia_force, args.moment, args.torque
    s_out, dyad_meas = args.stroke, args.dyad_measure
    kops, kf, jkind = args.load_ops, args.load_data, args.joint_kind
    gops, gf = args.frame_ops, args.frame_data
    n_lam, applied, lam_out, peak_out = args.n_multipliers, args.applied, args.multipliers, args.peaks
    N = force.shape[1]
    S = dz.shape[1]
    nb = mass.shape[1]
    P = S - nb
    rates = rate_out.shape[0] > 0
    msum = 0.0
    for i in range(nb):
        msum += mass[v, i]
    pos = np.zeros(S, dtype=np.complex128)
    vel = np.zeros(S, dtype=np.complex128)
    acc = np.zeros(S, dtype=np.complex128)
    rot = np.ones(nb, dtype=np.complex128)
    w = np.zeros(nb)
    al = np.zeros(nb)
    ph = np.zeros(nb)
    loads = kops.shape[0] > 0
    need_f = np.zeros(nb, dtype=np.complex128)
    need_m = np.zeros(nb)
    lam = np.zeros(n_lam)
    if loads:
        for q in range(jkind.shape[0]):
            peak_out[v, q] = 0.0
    for k in range(N):
        for g in grounded:
            pos[g] = dz[v, g]
        for o in range(ops.shape[0]):
            kind, t, k1, k2, b = ops[o, 0], ops[o, 1], ops[o, 2], ops[o, 3], ops[o, 4]
            if kind == 0:  # crank: turned by step × k from the drawing
                rot[b] = turn[k]
                ph[b] = np.angle(turn[k]) if rates else 0.0
                w[b] = omega[vw, k]
                al[b] = alpha[vw, k]
            elif kind == 1:  # rigid body from two known points
                dn = pos[k2] - pos[k1]
                dd = dz[v, k2] - dz[v, k1]
                inv = fdata[v, o, 0]  # 1/|dd|² = 1/|dn|²: a rigid body keeps its lengths
                rot[b] = dn * np.conj(dd) * inv
                ph[b] = np.angle(rot[b]) if rates else 0.0
                n2 = 1.0 / inv
                dv = vel[k2] - vel[k1]
                da = acc[k2] - acc[k1]
                w[b] = (dn.real * dv.imag - dn.imag * dv.real) / n2
                al[b] = (dn.real * da.imag - dn.imag * da.real) / n2
            elif kind == 2:  # a slider translating on a frame guide
                rot[b] = 1.0 + 0.0j
                ph[b] = 0.0
                w[b] = 0.0
                al[b] = 0.0
            elif kind == 3:  # a point of body b, from its point k1
                r = rot[b] * (dz[v, t] - dz[v, k1])
                pos[t] = pos[k1] + r
                vel[t] = vel[k1] + 1j * r * w[b]
                acc[t] = acc[k1] + r * (1j * al[b] - w[b] * w[b])
            elif kind == 4:  # RRR dyad
                r1, r2, sg = fdata[v, o, 0], fdata[v, o, 1], fdata[v, o, 2]
                d = pos[k2] - pos[k1]
                dist = np.sqrt(d.real * d.real + d.imag * d.imag)
                if dist == 0.0:  # the two known points coincide: no dyad (complex division would raise)
                    dist = np.nan
                x = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist)
                h2 = r1 * r1 - x * x
                if h2 < 0.0:
                    h2 = np.nan
                pp = pos[k1] + _over(d, dist) * (x + 1j * sg * np.sqrt(h2))
                a1 = pp - pos[k1]
                a2 = pp - pos[k2]
                det = a1.real * a2.imag - a1.imag * a2.real
                if dyad_meas.shape[0] > 0:  # sine of the transmission angle, signed
                    n1 = a1.real * a1.real + a1.imag * a1.imag
                    n2 = a2.real * a2.real + a2.imag * a2.imag
                    dyad_meas[lane, k, ops[o, 5]] = det / np.sqrt(n1 * n2)
                if det == 0.0:  # the links in line: velocities undefined (complex division would raise)
                    det = np.nan
                b1 = a1.real * vel[k1].real + a1.imag * vel[k1].imag
                b2 = a2.real * vel[k2].real + a2.imag * vel[k2].imag
                vv = complex((b1 * a2.imag - b2 * a1.imag) / det, (a1.real * b2 - a2.real * b1) / det)
                e1 = vv - vel[k1]
                e2 = vv - vel[k2]
                c1 = a1.real * acc[k1].real + a1.imag * acc[k1].imag - (e1.real * e1.real + e1.imag * e1.imag)
                c2 = a2.real * acc[k2].real + a2.imag * acc[k2].imag - (e2.real * e2.real + e2.imag * e2.imag)
                pos[t] = pp
                vel[t] = vv
                acc[t] = complex((c1 * a2.imag - c2 * a1.imag) / det, (a1.real * c2 - a2.real * c1) / det)
            else:  # RRP dyad: a link end on a frame guide through the point's drawing position
                L, sg = fdata[v, o, 0], fdata[v, o, 1]
                u = fdata[v, o, 2] + 1j * fdata[v, o, 3]
                q0 = dz[v, t]
                wq = q0 - pos[k1]
                bq = wq.real * u.real + wq.imag * u.imag
                disc = bq * bq - (wq.real * wq.real + wq.imag * wq.imag - L * L)
                if disc < 0.0:
                    disc = np.nan
                sp = -bq + sg * np.sqrt(disc)
                pp = q0 + sp * u
                rel = pp - pos[k1]
                den = rel.real * u.real + rel.imag * u.imag
                if dyad_meas.shape[0] > 0:
                    dyad_meas[lane, k, ops[o, 5]] = den / np.sqrt(rel.real * rel.real + rel.imag * rel.imag)
                if den == 0.0:
                    den = np.nan
                sd = (rel.real * vel[k1].real + rel.imag * vel[k1].imag) / den
                vv = sd * u
                e = vv - vel[k1]
                sdd = (
                    rel.real * acc[k1].real + rel.imag * acc[k1].imag - (e.real * e.real + e.imag * e.imag)
                ) / den
                pos[t] = pp
                vel[t] = vv
                acc[t] = sdd * u
        # the inertia force −Σ m a_G (a kinematic quantity, not a load)
        f = 0.0 + 0.0j
        for i in range(nb):
            f += mass[v, i] * (grav - acc[P + i])
        inertia_force[lane, k] = f - grav * msum
        if loads:
            # every load from the multipliers λ, solved dyad by dyad from the output back to the
            # crank (Assur groups: each dyad's Newton–Euler equations are a 2×2 system by moments
            # about its inner pin, Cramer's rule), then the frame's share from its joints
            for i in range(nb):
                need_f[i] = mass[v, i] * (acc[P + i] - grav)
                need_m[i] = inertia[v, i] * al[i]
                if applied.shape[0] > 0:
                    need_f[i] -= applied[lane, k, i, 0] + 1j * applied[lane, k, i, 1]
                    need_m[i] -= applied[lane, k, i, 2]
            for q in range(lam.shape[0]):
                lam[q] = 0.0
            for o in range(kops.shape[0]):
                op = kops[o]
                kind = op[0]
                if kind == 0:  # RRR: P, K1, K2, b1, b2, j1, s1, o1, j2, s2, o2, kp, sp
                    Pp = pos[op[1]]
                    a1 = pos[op[2]] - Pp
                    a2 = pos[op[3]] - Pp
                    b1, b2 = op[4], op[5]
                    f1, f2 = need_f[b1], need_f[b2]
                    m1 = need_m[b1] - _cross(Pp - pos[P + b1], f1)
                    m2 = _cross(a2, f1 + f2) - need_m[b2] + _cross(Pp - pos[P + b2], f2)
                    det = _cross(a1, a2)
                    if det == 0.0:  # the links in line: the forces are undefined
                        det = np.nan
                    F1 = _over(a2 * m1 - a1 * m2, det)
                    F2 = f1 + f2 - F1
                    Fp = F1 - f1
                    for side in range(2):
                        jj, sg, ot = op[6 + 3 * side], op[7 + 3 * side], op[8 + 3 * side]
                        F = F1 if side == 0 else F2
                        pt = op[2 + side]
                        lam[2 * jj] = sg * F.real
                        lam[2 * jj + 1] = sg * F.imag
                        if ot >= 0:
                            need_f[ot] += F
                            need_m[ot] += _cross(pos[pt] - pos[P + ot], F)
                    lam[2 * op[12]] = op[13] * Fp.real
                    lam[2 * op[12] + 1] = op[13] * Fp.imag
                elif kind == 1:  # RRP: P, K1, -, b1, slider, j1, s1, o1, kp, sp, kg
                    Pp = pos[op[1]]
                    a1 = pos[op[2]] - Pp
                    b1, sl = op[4], op[5]
                    n = kf[o, 0] + 1j * kf[o, 1]
                    m1 = need_m[b1] - _cross(Pp - pos[P + b1], need_f[b1])
                    total = need_f[b1] + need_f[sl]
                    across = _cross(a1, n)
                    if across == 0.0:  # the link along the guide: the forces are undefined
                        across = np.nan
                    normal = (_cross(a1, total) - m1) / across
                    Fp = need_f[sl] - normal * n
                    F1 = need_f[b1] + Fp
                    mom = need_m[sl] - _cross(Pp - pos[P + sl], need_f[sl])
                    jj, sg, ot = op[6], op[7], op[8]
                    lam[2 * jj] = sg * F1.real
                    lam[2 * jj + 1] = sg * F1.imag
                    if ot >= 0:
                        need_f[ot] += F1
                        need_m[ot] += _cross(pos[op[2]] - pos[P + ot], F1)
                    lam[2 * op[9]] = op[10] * Fp.real
                    lam[2 * op[9] + 1] = op[10] * Fp.imag
                    lam[2 * op[11] + 1] = -normal  # the guide: force −λ₂ n and moment −λ₁ on the slider
                    lam[2 * op[11]] = -mom
                else:  # the crank: pivot, -, -, crank, -, j0, s0
                    cr = op[4]
                    F0 = need_f[cr]
                    T = need_m[cr] - _cross(pos[op[1]] - pos[P + cr], F0)
                    lam[2 * op[6]] = op[7] * F0.real
                    lam[2 * op[6] + 1] = op[7] * F0.imag
                    lam[lam.shape[0] - 1] = -T
            # the frame's share: its joints' reactions and the motor's (−T)
            ff = 0.0 + 0.0j
            fm = lam[lam.shape[0] - 1]
            for g in range(gops.shape[0]):
                jj, sg, pt = gops[g, 1], gops[g, 2], gops[g, 3]
                if gops[g, 0] == 0:  # a pin to the frame
                    F = sg * (lam[2 * jj] + 1j * lam[2 * jj + 1])
                else:  # a frame guide: λ₂ n at the slider point, and the couple λ₁
                    F = lam[2 * jj + 1] * (gf[g, 0] + 1j * gf[g, 1])
                    fm += lam[2 * jj]
                ff += F
                fm += _cross(pos[pt], F)
            force[lane, k] = ff
            moment[lane, k] = fm
            torque[lane, k] = -lam[lam.shape[0] - 1]
            for q in range(jkind.shape[0]):  # each joint's largest force over the cycle (squared here)
                x = lam[2 * q] if jkind[q] == 0 else 0.0
                mag2 = x * x + lam[2 * q + 1] * lam[2 * q + 1]
                if mag2 > peak_out[v, q]:
                    peak_out[v, q] = mag2
            if lam_out.shape[0] > 0:
                for q in range(lam.shape[0]):
                    lam_out[lane, k, q] = lam[q]
        if out_slot >= 0:
            d = pos[out_slot] - dz[v, out_slot]
            s_out[lane, k] = d.real * u_out.real + d.imag * u_out.imag
        for j in range(keep.shape[0]):
            pos_out[lane, k, j] = pos[keep[j]]
        if vel_out.shape[0] > 0:  # the summary-only batch keeps positions alone
            for j in range(keep.shape[0]):
                vel_out[lane, k, j] = vel[keep[j]]
                acc_out[lane, k, j] = acc[keep[j]]
        if rates:
            for i in range(nb):
                rate_out[lane, k, i, 0] = ph[i]
                rate_out[lane, k, i, 1] = w[i]
                rate_out[lane, k, i, 2] = al[i]
    if loads:
        for q in range(jkind.shape[0]):
            peak_out[v, q] = np.sqrt(peak_out[v, q])


@numba.njit(parallel=True, cache=True, error_model="numpy")
def run_parallel(args):
    """Every variant (the leading axis of the arrays in ``args``) in parallel threads."""
    for v in numba.prange(args.drawing.shape[0]):
        variant(np.int64(v), args, np.int64(v))  # prange's index is unsigned: one signature of variant


@numba.njit(cache=True, error_model="numpy")
def run_serial(args):
    """Every variant in turn (one design: no threads to start)."""
    for v in range(args.drawing.shape[0]):
        variant(v, args, v)
