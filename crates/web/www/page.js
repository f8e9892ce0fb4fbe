// aograph's web page: the controls are generated from the techniques' parameter descriptions
// (WebPage.catalogue(), the same descriptions `aograph techniques` prints), every change is
// applied live as the `[ao]` TOML a config file would hold, and frames are timed by GPU
// timestamps per pass where the browser has them, and by the page's wall clock.
//
// ?scene=NAME picks a procedural scene; ?gltf=URL fetches a .glb instead; ?technique=NAME is
// the one shown first. With ?present=copy frames are drawn into a texture and copied into a 2D
// canvas, for browsers that cannot present a WebGPU canvas (headless Chromium's software
// adapter). With ?test=a,b,c the page instead renders each technique for FRAMES frames at
// 240x135 (copied out) and POSTs its AO and pass times to /report (scripts/web-test.sh).
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

// The AO of every technique first (FRAMES frames each, in order, as the native run does them),
// then, where the device has timestamps, a few more frames of each until its pass times arrive
// (they come frames late), so that timing changes no frame the AO is compared on.
async function runTest(page, techniques) {
  const results = [];
  for (const technique of techniques) {
    const result = { technique, adapter: page.adapter(), errors: [], wall_ms: [], timings: null };
    try {
      page.set_settings(`technique = "${technique}"`);
      for (let i = 0; i < FRAMES; i++) result.wall_ms.push(await page.frame());
      result.ao = base64(await page.read_ao());
      result.width = 240;
      result.height = 135;
    } catch (e) {
      result.errors.push(String(e));
    }
    result.errors.push(...page.take_errors());
    results.push(result);
  }
  for (const result of results) {
    if (result.errors.length) continue;
    try {
      page.set_settings(`technique = "${result.technique}"`);
      const ours = (t) => t.passes.some(([name]) => name.startsWith(result.technique + '.'));
      for (let i = 0; i < 12; i++) {
        await page.frame();
        result.timings = JSON.parse(page.pass_timings());
        if (!result.timings || ours(result.timings)) break;
      }
    } catch (e) {
      result.errors.push(String(e));
    }
    result.errors.push(...page.take_errors());
  }
  for (const result of results) await report(result);
  await report({ done: true });
}

// One control per parameter, from its description. A parameter without a default (an
// override such as "the preset's") gets an empty choice first, which leaves it unset; only
// values the user changed from the default are sent.
function control(p, onChange) {
  const wrap = document.createElement('div');
  const label = document.createElement('label');
  label.textContent = p.name;
  const doc = document.createElement('p');
  doc.className = 'doc';
  doc.textContent = `${p.doc} (allowed ${p.allowed}${p.unset ? '; unset: ' + p.unset : ''})`;
  const unsetOption = (select) => select.add(new Option(`(unset: ${p.unset || 'default'})`, '', false, true));
  let input;
  let valueOf;
  if (p.kind === 'bool' && p.default !== null) {
    input = document.createElement('input');
    input.type = 'checkbox';
    input.checked = p.default === true;
    valueOf = () => (input.checked === p.default ? null : String(input.checked));
  } else if (p.kind === 'bool' || p.kind === 'choice') {
    input = document.createElement('select');
    if (p.default === null) unsetOption(input);
    for (const c of p.kind === 'bool' ? [true, false] : p.choices) {
      input.add(new Option(String(c), String(c), false, c === p.default));
    }
    valueOf = () => {
      const v = input.value;
      if (v === '' || v === String(p.default)) return null;
      return p.kind === 'bool' ? v : JSON.stringify(v);
    };
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
    valueOf = () => {
      const v = input.value.trim();
      if (v === '' || v === String(p.default)) return null;
      // A number as it is; anything else (a word) as a TOML string, so that aograph's own
      // check answers what is allowed.
      return /^-?\d+(\.\d+)?([eE][-+]?\d+)?$/.test(v) ? v : JSON.stringify(v);
    };
  }
  input.id = `param-${p.name}`;
  label.htmlFor = input.id;
  input.addEventListener('change', onChange);
  if (input.type === 'checkbox') {
    label.prepend(input);
    wrap.append(label, doc);
  } else {
    wrap.append(label, doc, input);
  }
  return { name: p.name, wrap, valueOf };
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
      const v = c.valueOf();
      if (v !== null) lines.push(`${c.name} = ${v}`);
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
    for (const c of controls) params.append(c.wrap);
    apply();
  };
  if (query.get('technique')) select.value = query.get('technique');
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
      const gpu = JSON.parse(page.pass_timings());
      let text = `${page.technique()}: ${average.toFixed(1)} ms per frame, wall time from recording to GPU completion`;
      if (gpu && gpu.passes.length) {
        const total = gpu.passes.reduce((sum, [, ms]) => sum + ms, 0);
        text += `\nGPU timestamps at each pass's boundaries (frame ${gpu.frame}; copies and custom passes untimed):\n`;
        text += gpu.passes.map(([name, ms]) => `  ${name}: ${ms.toFixed(3)} ms`).join('\n');
        text += `\n  total: ${total.toFixed(3)} ms`;
      } else if (!gpu) {
        text += '\n(this browser offers no timestamp-query: no per-pass GPU times)';
      }
      timing.textContent = text;
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
    const gltf = query.get('gltf');
    if (gltf) {
      // A .glb (or a .gltf with embedded buffers) by URL, loaded by aograph's own importer.
      const response = await fetch(gltf);
      if (!response.ok) throw new Error(`${gltf}: HTTP ${response.status} ${response.statusText}`);
      const bytes = new Uint8Array(await response.arrayBuffer());
      page = await WebPage.start_gltf(canvas, gltf, bytes, copyOut);
    } else {
      page = await WebPage.start(canvas, query.get('scene') || 'corner', copyOut);
    }
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
