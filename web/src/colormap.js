// Colour scales for per-vertex and per-face fields.

// Viridis, sampled at 9 stops and interpolated linearly (t in [0, 1]).
const VIRIDIS = [[68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141], [39, 173, 129],
                 [92, 200, 99], [170, 220, 50], [253, 231, 37]];
export function viridis(t) {
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 1)) * (VIRIDIS.length - 1);
  const i = Math.min(VIRIDIS.length - 2, Math.floor(x)), f = x - i;
  return VIRIDIS[i].map((c, k) => (c + f * (VIRIDIS[i + 1][k] - c)) / 255);
}

// Diverging blue-white-red for signed fields (t in [-1, 1]).
export function diverging(t) {
  const x = Math.min(1, Math.max(-1, Number.isFinite(t) ? t : 0));
  return x < 0 ? [1 + x * 0.8, 1 + x * 0.6, 1] : [1, 1 - x * 0.6, 1 - x * 0.8];
}

export function cssGradient(scale) {
  const stops = [];
  for (let i = 0; i <= 8; ++i) {
    const t = i / 8;
    const [r, g, b] = scale === 'diverging' ? diverging(2 * t - 1) : viridis(t);
    stops.push(`rgb(${Math.round(r * 255)},${Math.round(g * 255)},${Math.round(b * 255)}) ${t * 100}%`);
  }
  return `linear-gradient(to right, ${stops.join(',')})`;
}

// Robust range of a field: [min, p99] ignoring non-finite values (one bad face must not wash out the scale).
export function robustRange(values) {
  const v = Array.from(values).filter(Number.isFinite).sort((a, b) => a - b);
  if (!v.length) return [0, 1];
  const hi = v[Math.min(v.length - 1, Math.ceil(0.99 * v.length) - 1)];
  return [v[0], hi > v[0] ? hi : v[0] + 1e-12];
}
