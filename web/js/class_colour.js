// One colour per class, the same in every session and page (a hash of the name).
export function classColour(name) {
  let h = 0;
  for (const c of String(name)) h = (h * 31 + c.codePointAt(0)) >>> 0;
  return `hsl(${(h * 137.508) % 360}, 85%, 58%)`;
}
