"""The reduced tippe-top equations (docs/physics.md#kinematics–§normal-force, §friction-laws) in scipy, for
cross-checks and the performance comparison (benches/compare/README.md).

Usage: python3 reduced_scipy.py classical|nano [--law sliding|regularized] [--eps E]
       [--rtol R] [--contact bilateral|paper] [--t-end T]
Prints t, theta, Omega, omega at 11 points and the wall time.
"""
import argparse, math, time
import numpy as np
from scipy.integrate import solve_ivp

def preset(name):
    if name == "nano":
        R = 3.55e-10; m = 1.196e-24; A = 2/3*m*R*R
        return dict(R=R, a=0.1*R, m=m, A=A, C=0.5*A, mu=0.13, g=9.8, H=(1e-22, 1e-22), t_end=1e-4)
    R = 0.015; m = 0.015; I = 0.4*m*R*R
    return dict(R=R, a=0.1*R, m=m, A=I, C=I, mu=0.1, g=9.8, H=(0.0, 0.0), t_end=10.0)

def make_rhs(p, law, eps, contact):
    R, a, m, A, C, mu, g = (p[k] for k in ("R", "a", "m", "A", "C", "mu", "g"))
    Hx, Hy = p["H"]
    def f(v):
        if law == "regularized":
            d = math.sqrt(v[0]**2 + v[1]**2 + eps**2)
        else:
            d = math.hypot(v[0], v[1])
            if d == 0.0:
                return 0.0, 0.0
        return mu*v[0]/d, mu*v[1]/d
    def rhs(t, y):
        th, thd, Om, w, ux, uy = y[:6]
        s, c = math.sin(th), math.cos(th)
        h = R - a*c
        vx = ux - h*thd
        vy = uy + s*(R*(w - Om*c) + a*Om)
        fx, fy = f((vx, vy))
        G = -Om*(C*w - A*Om*c)*s
        Q = m*g + m*a*c*thd**2 + m*a*s*(G + h*Hx)/A
        if contact == "paper":
            N = Q/(1 + m*a*s*(a*s - h*fx)/A)
            Nf = N
        else:
            Np = Q/(1 + m*a*s*(a*s - h*fx)/A)
            N = Np if Np >= 0 else Q/(1 + m*a*s*(a*s + h*fx)/A)
            Nf = abs(N)
        Fx = -Nf*fx - Hx
        Fy = -Nf*fy - Hy
        thdd = (G - a*s*N - h*Fx)/A
        Omd = (thd*(C*w - 2*A*Om*c) + (a - R*c)*Fy)/(A*s)
        wd = R*s*Fy/C
        return [thd, thdd, Omd, wd, Om*uy + Fx/m, -Om*ux + Fy/m]
    return rhs

if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("preset"); ap.add_argument("--law", default="sliding")
    ap.add_argument("--eps", type=float, default=1e-3); ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--contact", default="bilateral"); ap.add_argument("--t-end", type=float)
    ap.add_argument("--method", default="DOP853")
    o = ap.parse_args()
    p = preset(o.preset)
    T = o.t_end or p["t_end"]
    y0 = [0.1, 0.0, 0.0, 100.0, 0.0, 0.0]
    rhs = make_rhs(p, o.law, o.eps, o.contact)
    # Absolute tolerances scaled like tippetop's: lengths by R, times by 1/rate.
    rate = max(100.0, math.sqrt(p["g"]/p["R"]), math.sqrt(math.hypot(*p["H"])/(p["m"]*p["R"])))
    atol = o.rtol*np.array([1, rate, rate, rate, p["R"]*rate, p["R"]*rate])
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0, T), y0, method=o.method, rtol=o.rtol, atol=atol, dense_output=True)
    wall = time.perf_counter() - t0
    for t in np.linspace(0, T, 11):
        y = sol.sol(t)
        print(f"{t:.6e} theta={y[0]:.10f} Omega={y[2]:.6e} omega={y[3]:.6e} ux={y[4]:.3e} uy={y[5]:.3e}")
    print(f"status={sol.status} nfev={sol.nfev} wall={wall:.3f}s")
