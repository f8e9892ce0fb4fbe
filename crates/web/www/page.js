// aograph's web page: the controls are generated from the techniques' parameter descriptions
// (WebPage.catalogue(), the same descriptions `aograph techniques` prints), every change is
// applied live as the `[ao]` TOML a config file would hold, and frames are timed by the page's
// wall clock. With ?test=a,b,c the page instead renders each technique for FRAMES frames at
// 240x135 and POSTs its AO to /report (scripts/web-test.sh). With ?present=copy (and in test
// mode) frames are drawn into a texture and copied into a 2D canvas, for browsers that cannot
// present a WebGPU canvas (headless Chromium's software adapter).
import init, { WebPage } from './pkg/aograph_web.js';

const query = new URLSearchParams(location.search);
const FRAMES = 4;
// ?hold: the page's load event waits (an image the test server answers late) until frames have
// been drawn, so that a headless browser's --screenshot, taken at load, shows them.
if (query.has('hold')) {
  const img = new Image();
  img.hidden = true;
  img.src = '/hold';
  document.body.append(img);
}
let drawn = 0;

async function report(body) {
  await fetch('/report', { method: 'POST', body: JSON.stringify(body) });
}

function base64(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

async function runTest(page, techniques) {
  for (const technique of techniques) {
    const result = { technique, adapter: page.adapter(), errors: [], wall_ms: [] };
    try {
      page.set_settings(`technique = "${technique}"`);
      for (let i = 0; i < FRAMES; i++) result.wall_ms.push(await page.frame());
      const ao = await page.read_ao();
      result.width = 240;
      result.height = 135;
      result.ao = base64(ao);
    } catch (e) {
      result.errors.push(String(e));
    }
    result.errors.push(...page.take_errors());
    await report(result);
  }
  await report({ done: true });
}

// One control per parameter, from its description.
function control(p, onChange) {
  const wrap = document.createElement('div');
  const label = document.createElement('label');
  label.textContent = p.name;
  const doc = document.createElement('p');
  doc.className = 'doc';
  doc.textContent = `${p.doc} (allowed ${p.allowed}${p.unset ? '; unset: ' + p.unset : ''})`;
  let input;
  if (p.kind === 'bool') {
    input = document.createElement('input');
    input.type = 'checkbox';
    input.checked = p.default === true;
    input.value_of = () => (input.checked ? 'true' : 'false');
  } else if (p.kind === 'choice') {
    input = document.createElement('select');
    for (const c of p.choices) input.add(new Option(c, c, false, c === p.default));
    input.value_of = () => JSON.stringify(input.value);
  } else {
    input = document.createElement('input');
    input.type = p.kind === 'range' ? 'number' : 'text';
    if (p.kind === 'range') {
      input.min = p.min;
      input.max = p.max;
      input.step = p.integer ? (p.odd ? 2 : 1) : 'any';
    }
    input.value = p.default === null ? '' : p.default;
    input.placeholder = p.unset || '';
    input.value_of = () => {
      const v = input.value.trim();
      if (v === '') return null;
      if (p.kind === 'word_or_number' && v === p.word) return JSON.stringify(v);
      return v;
    };
  }
  input.id = `param-${p.name}`;
  label.htmlFor = input.id;
  input.addEventListener('change', onChange);
  if (p.kind === 'bool') {
    label.prepend(input);
    wrap.append(label, doc);
  } else {
    wrap.append(label, doc, input);
  }
  return { name: p.name, input, changed: () => input.value_of() !== null && String(p.default) !== input.value.trim() && !(p.kind === 'bool' && input.checked === p.default) };
}

function interactive(page, canvas, copyOut) {
  const context2d = copyOut ? canvas.getContext('2d') : null;
  const catalogue = JSON.parse(page.catalogue());
  const select = document.getElementById('technique');
  const radius = document.getElementById('radius');
  const params = document.getElementById('params');
  const error = document.getElementById('error');
  let controls = [];
  document.getElementById('adapter').textContent = `adapter: ${page.adapter()}`;
  radius.value = page.radius();
  for (const t of catalogue) select.add(new Option(t.name, t.name, false, t.name === page.technique()));

  const apply = () => {
    const t = select.value;
    const lines = [`technique = "${t}"`, `radius = ${Number(radius.value) || page.radius()}`, `[${t}]`];
    for (const c of controls) {
      const v = c.input.value_of();
      if (v !== null && c.changed()) lines.push(`${c.name} = ${v}`);
    }
    try {
      page.set_settings(lines.join('\n'));
      error.textContent = '';
    } catch (e) {
      error.textContent = String(e);
    }
  };
  const showTechnique = () => {
    const t = catalogue.find((x) => x.name === select.value);
    document.getElementById('description').textContent = t.description;
    params.replaceChildren();
    controls = t.parameters.map((p) => control(p, apply));
    for (const c of controls) params.append(c.input.closest('div') || c.input.parentElement);
    apply();
  };
  select.addEventListener('change', showTechnique);
  radius.addEventListener('change', apply);
  document.getElementById('ao-only').addEventListener('change', (e) => page.set_ao_only(e.target.checked));
  showTechnique();

  const timing = document.getElementById('timing');
  let average = null;
  const tick = async () => {
    try {
      const ms = await page.frame();
      if (context2d) {
        const rgba = await page.read_color();
        context2d.putImageData(new ImageData(new Uint8ClampedArray(rgba), canvas.width, canvas.height), 0, 0);
      }
      average = average === null ? ms : 0.9 * average + 0.1 * ms;
      timing.textContent = `${page.technique()}: ${average.toFixed(1)} ms per frame, wall time from recording to GPU completion (this browser gives a device without timestamp queries inside encoders, so no per-pass GPU times)`;
      if (++drawn === 12 && query.has('hold')) await fetch('/drawn', { method: 'POST' });
      const errors = page.take_errors();
      if (errors.length) error.textContent = errors.join('\n');
    } catch (e) {
      error.textContent = String(e);
    }
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

async function main() {
  await init();
  const canvas = document.getElementById('view');
  const test = query.get('test');
  const copyOut = Boolean(test) || query.get('present') === 'copy';
  if (test) {
    canvas.width = 240;
    canvas.height = 135;
  }
  let page;
  try {
    page = await WebPage.start(canvas, query.get('scene') || 'corner', copyOut);
  } catch (e) {
    if (test) await report({ error: String(e) });
    document.getElementById('error').textContent = String(e);
    return;
  }
  if (test) await runTest(page, test.split(','));
  else interactive(page, canvas, copyOut);
}

main().catch(async (e) => {
  document.getElementById('error').textContent = String(e);
  if (query.get('test')) await report({ error: String(e) });
});
