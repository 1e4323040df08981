// Free practice's stock and tools: kept in the browser (localStorage), and the stock as the API wants it.
const SETUP_KEY = "paltrainer-practice-setup";
const DEFAULT_SETUP = { size: [80, 70, 30], tools: [] };  // the PAL examples' block; tools: the default table

export function practiceSetup() {
  try {
    const saved = JSON.parse(localStorage.getItem(SETUP_KEY));
    if (saved && saved.size?.length === 3 && Array.isArray(saved.tools)) return saved;
  } catch { /* a damaged entry: start afresh */ }
  return structuredClone(DEFAULT_SETUP);
}

export function saveSetup(setup) { localStorage.setItem(SETUP_KEY, JSON.stringify(setup)); }

// The stock as the API wants it: zero at the front left corner of the top face.
export function stockOf(setup) {
  const [x, y, z] = setup.size;
  return { min: [0, 0, -z], max: [x, y, 0] };
}
