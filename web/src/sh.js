// Spherical harmonics in the browser, with exactly the conventions of core/sh/sh_basis.hpp and
// docs/design/sh-and-invariants.md:
//   * u = (sin t cos p, sin t sin p, cos t), t = colatitude, p = azimuth;
//   * j = l^2 + l + m, m = -l..l; (Lmax+1)^2 coefficients per coordinate;
//   * complex Y_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos t) e^{i m p}, P_l^m WITH the Condon-Shortley
//     phase (-1)^m; Y_l^{-m} = (-1)^m conj(Y_l^m);
//   * the surface x_L(u) = Re sum_{l <= L} sum_m c_l^m Y_l^m(u) (core/sh/sh_reconstruction.hpp keeps the real part).
// The associated Legendre functions are the fully normalised ones, by the standard three-term recurrences (no
// factorials), as sh_basis.cpp does.

export const shIndex = (l, m) => l * l + l + m;
export const shCount = (lmax) => (lmax + 1) * (lmax + 1);

// Recurrence tables of one Lmax: Pbar_l^m = a_lm (z Pbar_{l-1}^m - b_lm Pbar_{l-2}^m).
export function legendreTables(lmax) {
  const n = lmax + 1;
  const a = new Float64Array(n * n), b = new Float64Array(n * n);
  for (let m = 0; m <= lmax; ++m) {
    for (let l = m + 2; l <= lmax; ++l) {
      a[l * n + m] = Math.sqrt((4 * l * l - 1) / (l * l - m * m));
      b[l * n + m] = Math.sqrt(((l - 1) * (l - 1) - m * m) / (4 * (l - 1) * (l - 1) - 1));
    }
  }
  return { lmax, a, b };
}

// Normalised P (including 1/sqrt(4 pi) and the CS phase) for all l <= lmax, 0 <= m <= l, at cos t = z,
// sin t = s >= 0: out[l * (lmax+1) + m] so that Y_l^m = out[..] e^{i m p}.
export function normalisedLegendre(tables, z, s, out) {
  const { lmax, a, b } = tables;
  const n = lmax + 1;
  let pmm = 1 / Math.sqrt(4 * Math.PI);
  for (let m = 0; m <= lmax; ++m) {
    if (m > 0) pmm *= -Math.sqrt((2 * m + 1) / (2 * m)) * s;  // CS phase: the minus sign
    out[m * n + m] = pmm;
    if (m + 1 <= lmax) out[(m + 1) * n + m] = Math.sqrt(2 * m + 3) * z * pmm;
    for (let l = m + 2; l <= lmax; ++l)
      out[l * n + m] = a[l * n + m] * (z * out[(l - 1) * n + m] - b[l * n + m] * out[(l - 2) * n + m]);
  }
  return out;
}

// Complex Y_l^m(t, p) for one (l, m), m may be negative: [re, im].
export function complexY(l, m, theta, phi) {
  const tables = legendreTables(l);
  const p = normalisedLegendre(tables, Math.cos(theta), Math.sin(theta), new Float64Array((l + 1) * (l + 1)));
  const am = Math.abs(m);
  const v = p[l * (l + 1) + am];
  let re = v * Math.cos(am * phi), im = v * Math.sin(am * phi);
  if (m < 0) {  // Y^{-m} = (-1)^m conj(Y^m)
    const sign = am % 2 ? -1 : 1;
    re *= sign;
    im *= -sign;
  }
  return [re, im];
}

// Coefficients as sent by the service (descriptor.coefficients: {x, y, z}, each (Lmax+1)^2 pairs [re, im]).
export function lmaxOfCoefficients(coefficients) {
  const k = coefficients.x.length;
  const lmax = Math.round(Math.sqrt(k)) - 1;
  if (shCount(lmax) !== k) throw new Error(`coefficient count ${k} is not a square (Lmax+1)^2`);
  return lmax;
}

// x_L at n sphere points (flat [x0, y0, z0, ...], unit or not), summing degrees 0..degree; returns a Float64Array
// of 3n positions.
export function evaluateSurface(coefficients, spherePoints, degree) {
  const lmax = lmaxOfCoefficients(coefficients);
  const L = Math.max(0, Math.min(degree, lmax));
  const tables = legendreTables(L);
  const n = L + 1;
  const p = new Float64Array(n * n);
  const cosm = new Float64Array(n), sinm = new Float64Array(n);
  const cx = coefficients.x, cy = coefficients.y, cz = coefficients.z;
  const count = spherePoints.length / 3;
  const out = new Float64Array(3 * count);
  for (let i = 0; i < count; ++i) {
    const ux = spherePoints[3 * i], uy = spherePoints[3 * i + 1], uz = spherePoints[3 * i + 2];
    const r = Math.hypot(ux, uy, uz);
    const z = uz / r, s = Math.hypot(ux, uy) / r;
    const phi = Math.atan2(uy, ux);
    normalisedLegendre(tables, z, s, p);
    for (let m = 0; m <= L; ++m) { cosm[m] = Math.cos(m * phi); sinm[m] = Math.sin(m * phi); }
    let X = 0, Y = 0, Z = 0;
    for (let l = 0; l <= L; ++l) {
      for (let m = -l; m <= l; ++m) {
        const am = Math.abs(m);
        const v = p[l * n + am];
        let yre = v * cosm[am], yim = v * sinm[am];
        if (m < 0) {
          const sign = am % 2 ? -1 : 1;
          yre *= sign;
          yim *= -sign;
        }
        const j = l * l + l + m;
        // Re(c Y) = c.re Y.re - c.im Y.im
        X += cx[j][0] * yre - cx[j][1] * yim;
        Y += cy[j][0] * yre - cy[j][1] * yim;
        Z += cz[j][0] * yre - cz[j][1] * yim;
      }
    }
    out[3 * i] = X; out[3 * i + 1] = Y; out[3 * i + 2] = Z;
  }
  return out;
}

// xi(l) = sum_m sum_{x,y,z} |c_l^m|^2 (paper Eq. 14), for checking the returned invariants.
export function invariants(coefficients) {
  const lmax = lmaxOfCoefficients(coefficients);
  const xi = new Array(lmax + 1).fill(0);
  for (const axis of ['x', 'y', 'z'])
    for (let l = 0; l <= lmax; ++l)
      for (let m = -l; m <= l; ++m) {
        const [re, im] = coefficients[axis][l * l + l + m];
        xi[l] += re * re + im * im;
      }
  return xi;
}

// Per-vertex |x_i - x_L(u_i)| and its mean / rms / max: the service's descriptor.fit_error at degree Lmax.
export function fitError(vertices, reconstructed) {
  const n = vertices.length / 3;
  const d = new Float64Array(n);
  let sum = 0, sum2 = 0, max = 0;
  for (let i = 0; i < n; ++i) {
    const e = Math.hypot(vertices[3 * i] - reconstructed[3 * i], vertices[3 * i + 1] - reconstructed[3 * i + 1],
                         vertices[3 * i + 2] - reconstructed[3 * i + 2]);
    d[i] = e; sum += e; sum2 += e * e; max = Math.max(max, e);
  }
  return { perVertex: d, mean: sum / n, rms: Math.sqrt(sum2 / n), max };
}
