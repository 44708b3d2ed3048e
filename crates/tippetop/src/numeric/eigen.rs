//! Eigenvalues of a small dense real matrix: balancing, reduction to upper
//! Hessenberg form and the Francis double-shift QR algorithm (EISPACK's
//! `balanc`, `elmhes`, `hqr`). The stability analysis needs the eigenvalues
//! of 5x5 to 7x7 Jacobians; the tests check them against the roots of
//! closed-form characteristic polynomials.

// Dense linear algebra on small matrices reads best with indices.
#![allow(clippy::needless_range_loop)]

/// Eigenvalues `(re, im)` of a real square matrix (rows), by balancing,
/// reduction to Hessenberg form and the Francis double-shift QR algorithm.
/// Returns `None` if QR does not converge (60 iterations per eigenvalue).
pub fn eigenvalues(m: &[Vec<f64>]) -> Option<Vec<(f64, f64)>> {
    let n = m.len();
    if n == 0 {
        return Some(vec![]);
    }
    let mut a: Vec<Vec<f64>> = m.to_vec();
    balance(&mut a);
    hessenberg(&mut a);
    for i in 0..n {
        for j in 0..n {
            if i > j + 1 {
                a[i][j] = 0.0;
            }
        }
    }
    hqr(&mut a)
}

fn balance(a: &mut [Vec<f64>]) {
    let n = a.len();
    const RADIX: f64 = 2.0;
    let sqrdx = RADIX * RADIX;
    loop {
        let mut done = true;
        for i in 0..n {
            let (mut r, mut c) = (0.0, 0.0);
            for j in 0..n {
                if j != i {
                    c += a[j][i].abs();
                    r += a[i][j].abs();
                }
            }
            if c != 0.0 && r != 0.0 {
                let mut g = r / RADIX;
                let mut f = 1.0;
                let s = c + r;
                while c < g {
                    f *= RADIX;
                    c *= sqrdx;
                }
                g = r * RADIX;
                while c > g {
                    f /= RADIX;
                    c /= sqrdx;
                }
                if (c + r) / f < 0.95 * s {
                    done = false;
                    let g = 1.0 / f;
                    for j in 0..n {
                        a[i][j] *= g;
                    }
                    for row in a.iter_mut() {
                        row[i] *= f;
                    }
                }
            }
        }
        if done {
            break;
        }
    }
}

fn hessenberg(a: &mut [Vec<f64>]) {
    let n = a.len();
    for m in 1..n.saturating_sub(1) {
        let mut x: f64 = 0.0;
        let mut i = m;
        for j in m..n {
            if a[j][m - 1].abs() > x.abs() {
                x = a[j][m - 1];
                i = j;
            }
        }
        if i != m {
            for j in (m - 1)..n {
                let t = a[i][j];
                a[i][j] = a[m][j];
                a[m][j] = t;
            }
            for row in a.iter_mut() {
                row.swap(i, m);
            }
        }
        if x != 0.0 {
            for i in (m + 1)..n {
                let mut y = a[i][m - 1];
                if y != 0.0 {
                    y /= x;
                    a[i][m - 1] = y;
                    for j in m..n {
                        a[i][j] -= y * a[m][j];
                    }
                    for row in a.iter_mut() {
                        row[m] += y * row[i];
                    }
                }
            }
        }
    }
}

/// Eigenvalues of an upper Hessenberg matrix by the Francis double-shift
/// QR iteration (EISPACK's `hqr`). A numerical kernel kept whole on
/// purpose (over 150 lines): one loop of deflation, exceptional shifts and
/// the double-shift sweep sharing their running sums; split, that state
/// would pass between pieces and the line-by-line match with the published
/// algorithm would be lost.
#[allow(clippy::many_single_char_names, unused_assignments)]
fn hqr(a: &mut [Vec<f64>]) -> Option<Vec<(f64, f64)>> {
    let n = a.len() as isize;
    let mut wr = vec![0.0; n as usize];
    let mut wi = vec![0.0; n as usize];
    let at = |i: isize| i as usize;
    let mut anorm = 0.0;
    for i in 0..n {
        for j in (i - 1).max(0)..n {
            anorm += a[at(i)][at(j)].abs();
        }
    }
    let sign = |a: f64, b: f64| if b >= 0.0 { a.abs() } else { -a.abs() };
    let mut nn = n - 1;
    let mut t = 0.0;
    let (mut p, mut q, mut r, mut s, mut w, mut x, mut y, mut z) = (
        0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64,
    );
    while nn >= 0 {
        let mut its = 0;
        loop {
            let mut l = nn;
            while l >= 1 {
                s = a[at(l - 1)][at(l - 1)].abs() + a[at(l)][at(l)].abs();
                if s == 0.0 {
                    s = anorm;
                }
                if a[at(l)][at(l - 1)].abs() + s == s {
                    a[at(l)][at(l - 1)] = 0.0;
                    break;
                }
                l -= 1;
            }
            x = a[at(nn)][at(nn)];
            if l == nn {
                wr[at(nn)] = x + t;
                wi[at(nn)] = 0.0;
                nn -= 1;
                break;
            }
            y = a[at(nn - 1)][at(nn - 1)];
            w = a[at(nn)][at(nn - 1)] * a[at(nn - 1)][at(nn)];
            if l == nn - 1 {
                p = 0.5 * (y - x);
                q = p * p + w;
                z = q.abs().sqrt();
                x += t;
                if q >= 0.0 {
                    z = p + sign(z, p);
                    wr[at(nn - 1)] = x + z;
                    wr[at(nn)] = x + z;
                    if z != 0.0 {
                        wr[at(nn)] = x - w / z;
                    }
                    wi[at(nn - 1)] = 0.0;
                    wi[at(nn)] = 0.0;
                } else {
                    wr[at(nn - 1)] = x + p;
                    wr[at(nn)] = x + p;
                    wi[at(nn - 1)] = -z;
                    wi[at(nn)] = z;
                }
                nn -= 2;
                break;
            }
            if its == 60 {
                return None;
            }
            if its == 10 || its == 20 || its == 40 {
                t += x;
                for i in 0..=nn {
                    a[at(i)][at(i)] -= x;
                }
                s = a[at(nn)][at(nn - 1)].abs() + a[at(nn - 1)][at(nn - 2)].abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            let mut m = nn - 2;
            while m >= l {
                z = a[at(m)][at(m)];
                r = x - z;
                s = y - z;
                p = (r * s - w) / a[at(m + 1)][at(m)] + a[at(m)][at(m + 1)];
                q = a[at(m + 1)][at(m + 1)] - z - r - s;
                r = a[at(m + 2)][at(m + 1)];
                s = p.abs() + q.abs() + r.abs();
                p /= s;
                q /= s;
                r /= s;
                if m == l {
                    break;
                }
                let u = a[at(m)][at(m - 1)].abs() * (q.abs() + r.abs());
                let v = p.abs()
                    * (a[at(m - 1)][at(m - 1)].abs() + z.abs() + a[at(m + 1)][at(m + 1)].abs());
                if u + v == v {
                    break;
                }
                m -= 1;
            }
            for i in (m + 2)..=nn {
                a[at(i)][at(i - 2)] = 0.0;
                if i != m + 2 {
                    a[at(i)][at(i - 3)] = 0.0;
                }
            }
            let mut k = m;
            while k < nn {
                if k != m {
                    p = a[at(k)][at(k - 1)];
                    q = a[at(k + 1)][at(k - 1)];
                    r = 0.0;
                    if k != nn - 1 {
                        r = a[at(k + 2)][at(k - 1)];
                    }
                    x = p.abs() + q.abs() + r.abs();
                    if x != 0.0 {
                        p /= x;
                        q /= x;
                        r /= x;
                    }
                }
                s = sign((p * p + q * q + r * r).sqrt(), p);
                if s != 0.0 {
                    if k == m {
                        if l != m {
                            a[at(k)][at(k - 1)] = -a[at(k)][at(k - 1)];
                        }
                    } else {
                        a[at(k)][at(k - 1)] = -s * x;
                    }
                    p += s;
                    x = p / s;
                    y = q / s;
                    z = r / s;
                    q /= p;
                    r /= p;
                    for j in k..=nn {
                        p = a[at(k)][at(j)] + q * a[at(k + 1)][at(j)];
                        if k != nn - 1 {
                            p += r * a[at(k + 2)][at(j)];
                            a[at(k + 2)][at(j)] -= p * z;
                        }
                        a[at(k + 1)][at(j)] -= p * y;
                        a[at(k)][at(j)] -= p * x;
                    }
                    let mmin = if nn < k + 3 { nn } else { k + 3 };
                    for i in l..=mmin {
                        p = x * a[at(i)][at(k)] + y * a[at(i)][at(k + 1)];
                        if k != nn - 1 {
                            p += z * a[at(i)][at(k + 2)];
                            a[at(i)][at(k + 2)] -= p * r;
                        }
                        a[at(i)][at(k + 1)] -= p * q;
                        a[at(i)][at(k)] -= p;
                    }
                }
                k += 1;
            }
        }
    }
    let mut out: Vec<(f64, f64)> = wr.into_iter().zip(wi).collect();
    out.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.total_cmp(&a.1)));
    Some(out)
}
