"""Compiled twins (numba) of a bound tether's per-step bookkeeping: the constraint rows of an
equality, the tension-only switching, the elements' running peak push, the drum element's
payout update, the divergence search and the snap-load detector's update (``snap``). The NumPy/Python code they twin (``drum``, ``slack``,
``readouts``, ``Simulation.check``) is the reference; ``tests/physics/test_compiled.py`` checks
each against it (the peak push: ``tests/cable/test_compression_peak.py``). Units SI."""

from __future__ import annotations

import math

import numpy as np

from mjtether.physics.compiled import jit


@jit
def equality_rows(efc_type, efc_id, nefc, eq_id, start, stop, equality):
    """``readouts.TetherReadouts.rows``: the rows (start, stop) of equality ``eq_id`` among the
    first ``nefc`` constraint rows (type ``equality``), a contiguous block; the block
    [``start``, ``stop``) given is checked at its ends and kept if it is still that equality's
    whole block, else found again by a search ((0, 0) if it has none)."""
    if 0 <= start < stop <= nefc and efc_type[start] == equality and efc_id[start] == eq_id \
            and efc_type[stop - 1] == equality and efc_id[stop - 1] == eq_id \
            and (start == 0 or efc_type[start - 1] != equality or efc_id[start - 1] != eq_id) \
            and (stop == nefc or efc_type[stop] != equality or efc_id[stop] != eq_id):
        return start, stop
    first, last = -1, -1
    for r in range(nefc):
        if efc_type[r] == equality and efc_id[r] == eq_id:
            if first < 0:
                first = r
            last = r
    return (first, last + 1) if first >= 0 else (0, 0)


@jit
def slack_switch(act, f, ten_length, rest, K, first, f_min, slack_tension, taut, all_rows):
    """``slack.SlackSwitch.update`` after its row lookup: ``act`` (n,) the elements'
    ``eq_active`` (switched in place), ``f`` the active elements' constraint forces in element
    order (N, > 0 pushes), ``ten_length``, ``rest`` (m) and ``K`` (N/m) per element; ``all_rows``:
    every deployed element had a row. Returns (changed, redo)."""
    n = act.shape[0]
    nf = f.shape[0]
    f_over = f_min  # an overshoot is worth a redo above this, or SLACK_TENSION of the highest tension
    if nf:
        lowest = f[0]
        for r in range(1, nf):
            lowest = min(lowest, f[r])
        f_over = max(f_min, -slack_tension * lowest)
    changed = redo = False
    if nf:
        off = np.zeros(n, dtype=np.bool_)
        push_max, pushed = -math.inf, False
        r = 0
        for e in range(n):  # an element whose equality pushed goes slack (the last pass: short ones and real pushes)
            if act[e]:
                if f[r] > 0.0 and (taut or ten_length[e] < rest[e] or f[r] > f_min):
                    off[e] = True
                    pushed = True
                    push_max = max(push_max, f[r])
                r += 1
        if pushed:
            for e in range(n):
                if off[e]:
                    act[e] = 0
            changed = True
            redo = push_max > f_min
    if taut and not all_rows:  # a slack element longer than its rest length is taut again
        over_max, caught = -math.inf, False
        for e in range(first, n):
            if act[e] == 0:
                over = ten_length[e] - rest[e]
                if over > 0.0:
                    act[e] = 1
                    caught = True
                    over_max = max(over_max, over * K[e])
        if caught:
            changed = True
            redo = redo or over_max > f_over
    return changed, redo


@jit
def peak_push(peak, act, f, first):
    """``readouts.TetherReadouts.track_peak_compression``: raise ``peak`` (n,) (N) in place to
    each element's push now: ``act`` (n,) the elements' ``eq_active`` when the forces were
    computed, ``f`` the active elements' constraint forces in element order (N, > 0 pushes);
    the elements before ``first`` (on the drum) are left as they are."""
    r = 0
    for e in range(act.shape[0]):
        if act[e]:
            if e >= first and f[r] > peak[e]:
                peak[e] = f[r]
            r += 1


@jit
def tether_extremes(v, stretch_from, rest):
    """``Simulation.check``'s search over one tether: (index of the largest |v| (the
    first NaN if any), that |v|, index of the largest ``stretch_from - rest``, that stretch)."""
    i, vmax = 0, -1.0
    for a in range(v.shape[0]):
        x = abs(v[a])
        if math.isnan(x):
            i, vmax = a, x
            break
        if x > vmax:
            i, vmax = a, x
    j, smax = 0, -math.inf
    for b in range(rest.shape[0]):
        s = stretch_from[b] - rest[b]
        if math.isnan(s):
            j, smax = b, s
            break
        if s > smax:
            j, smax = b, s
    return i, vmax, j, smax


@jit
def axial_scalar(EA, segment_length, inv_mass, timestep, damping_ratio, omega_dt, min_imp, max_imp):
    """``builder.axial_scalar`` (EA = inf: inextensible): (S, B, d)."""
    omega_cap = omega_dt / timestep
    K = EA / max(segment_length, 1e-12)
    x = min(max(omega_cap * omega_cap / (K * inv_mass), 1.0 - max_imp), 1.0 - min_imp)
    S = min(K * x * inv_mass, omega_cap * omega_cap)
    return S, 2.0 * damping_ratio * math.sqrt(S), 1.0 - x


@jit
def drum_update(k, n, l0, mu, s, c, ap, i_ref, dof0, tadr, eq0, nten, EA, dt, zeta, omega_dt, min_imp, max_imp,
                payout_rate, bids, rest, inertia, lead, K, body_mass, armature, invweight, ten_armature, eq_solref,
                eq_solimp, eq_data, tendon_length0):
    """``drum.Drum.update_drum``: an ordinary payout step's bookkeeping of the
    fairlead node ``k``, the first free node and the elements at them, written into the model's
    arrays (``body_mass``, ``dof_armature``, ``tendon_invweight0``, ``tendon_armature`` from
    ``nten`` on (-1: isotropic added mass), ``eq_solref``, ``eq_solimp``, ``eq_data``) and the
    tether's own (``rest``, ``inertia``, ``lead``, ``K``). ``s`` the drum element's rest length
    and ``c`` the fairlead's share of it (m), ``ap`` added mass per metre per element (kg/m)."""
    rest[k] = s
    right = l0 if k + 1 < n else 0.0
    for which in range(2):
        if which == 0:
            i, mass, add = k, mu * c, ap[k] * c
        else:
            i = k + 1
            mass = mu * ((s - c) + 0.5 * right)
            add = ap[k] * (s - c) + (0.5 * ap[k + 1] * right if k + 1 < n else 0.0)
        iso = max(i_ref - mass - add, 0.0) if (i == k or i == n) else 0.0
        if nten < 0:
            iso += add
        else:
            ten_armature[nten + 2 * i] = add
            ten_armature[nten + 2 * i + 1] = add
        iso = max(iso, 1e-9 * i_ref)
        body_mass[bids[i]] = mass
        dof = dof0 + 3 * i
        armature[dof] = armature[dof + 1] = armature[dof + 2] = iso
        inertia[i] = mass + iso
    for j in range(k, min(k + 2, n)):
        inv = 1.0 / inertia[j] + 1.0 / inertia[j + 1]
        S, B, d = axial_scalar(EA, rest[j], inv, dt, zeta, omega_dt, min_imp, max_imp)
        invweight[tadr + j] = inv
        e = eq0 + j
        eq_solref[e, 0] = -S
        eq_solref[e, 1] = -B
        eq_solimp[e, 0] = eq_solimp[e, 1] = d
        lead[j] = B / S
        K[j] = S / ((1.0 - d) * inv)
    eq_data[eq0 + k, 0] = s + lead[k] * payout_rate - tendon_length0[tadr + k]


@jit
def snap_update(t, act, f, first, slack, taut_at, window, slack_now, snapping, t_slack, t_taut, slack_for, peak,
                t_min, t_max, interval_max, closing, top_min):
    """``snap.SnapDetector.update`` at time ``t`` (s) from the constraint state (``act`` (n,) the
    elements' ``eq_active``, ``f`` the active elements' forces in element order, N, tension
    negative; elements before ``first`` on the drum): the detector's arrays updated in place,
    ``closing`` set for each snap that ended (its event read from ``t_taut``, ``peak`` and
    ``slack_for``); ``top_min`` (1,) the least tension of the element at ``first`` (the
    fairlead's) so far. Returns how many ended, or -(element + 1) for a non-finite force."""
    n = act.shape[0]
    closed = 0
    r = 0
    for e in range(n):
        T = 0.0
        if act[e]:
            T = -f[r]
            r += 1
            if not math.isfinite(T):
                return -(e + 1)
            if T < 0.0:
                T = 0.0
        if e < first:
            T = 0.0
            slack_now[e] = False
            if snapping[e]:
                snapping[e] = False
                closing[e] = True
                closed += 1
            if T > t_max[e]:
                t_max[e] = T
            continue
        if T < t_min[e]:
            t_min[e] = T
        if e == first and T < top_min[0]:
            top_min[0] = T
        if T > t_max[e]:
            t_max[e] = T
        if T > interval_max[e]:
            interval_max[e] = T
        low = T <= slack[e]
        if snapping[e]:
            if T > peak[e]:
                peak[e] = T
            if low or t - t_taut[e] >= window:
                snapping[e] = False
                closing[e] = True
                closed += 1
        if low and not slack_now[e]:
            t_slack[e] = t
            slack_now[e] = True
        if slack_now[e] and T > taut_at[e]:
            slack_now[e] = False
            snapping[e] = True
            t_taut[e] = t
            slack_for[e] = t - t_slack[e]
            peak[e] = T
    return closed
