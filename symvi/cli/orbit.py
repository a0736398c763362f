"""``symvi orbit``: the period-1 one-impact orbits at one forcing frequency."""
from . import add_params, params_from, print_json


def register(sub):
    p = sub.add_parser("orbit", help="period-1 one-impact orbits at one omega, eqs. (10)-(18)")
    add_params(p)
    p.add_argument("--omega", type=float, required=True, help="forcing frequency (> 0)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p


def run(args):
    from ..orbit import period1_orbits
    from ..params import check_omega, modal
    params = params_from(args)
    omega = check_omega(params, args.omega)
    orbits = period1_orbits(params, omega)
    if args.json:
        print_json({"params": params.as_dict(), "omega": omega,
                    "orbits": [o.as_dict() for o in orbits]})
        return 0
    m = modal(params)
    print(f"params: mu_m={params.mu_m:g} mu_k={params.mu_k:g} f2={params.f2:g} "
          f"b={params.b:g} r={params.r:g}   omega={omega:.10g}")
    print(f"modal:  omega1={m.omega1:.10g} omega2={m.omega2:.10g}")
    if not orbits:
        print("no period-1 one-impact orbit exists here (discriminant of eq. (16) negative)")
        return 0
    hdr = f"{'branch':6} {'x1dot+':>13} {'x20':>13} {'x20dot':>13} {'tau0':>13} " \
          f"{'v_impact':>13} {'max|lambda|':>11}  status"
    print(hdr)
    for o in orbits:
        lam = max(abs(complex(z)) for z in o.multipliers)
        status = ("stable" if o.stable else "unstable") if o.admissible else "INADMISSIBLE"
        print(f"{o.branch:6} {o.v1_plus:13.8f} {o.x20:13.8f} {o.x20_dot:13.8f} {o.tau0:13.8f} "
              f"{o.impact_velocity:13.8f} {lam:11.7f}  {status}")
        print("       multipliers: " + ", ".join(
            f"{complex(z).real:+.8f}{complex(z).imag:+.8f}i" for z in o.multipliers))
        if not o.admissible:
            print(f"       reason: {o.reason}")
    return 0
