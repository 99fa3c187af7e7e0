/* rigflow report viewer. Reads the data block written by the report node (report.html) and
 * draws it with three.js. Every text from a file (joint names, measure names, warnings) reaches
 * the page through textContent only, never as markup. */
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('rf-data').textContent);
  var HIGHLIGHT = 0xff00ff, CONTACT = 0xff2020;
  var SECTION_COLOURS = {
    root: 0x8c8c8c, spine: 0xe6c229, head: 0xf17105, tail: 0xa26769, arm: 0x1a8fe3,
    hand: 0x6fd3ff, leg: 0x2ca02c, foot: 0x9be564, appendage: 0xb388eb, helper: 0x555555
  };

  function el(tag, text, cls) {
    var e = document.createElement(tag);
    if (text !== undefined && text !== null) e.textContent = String(text);
    if (cls) e.className = cls;
    return e;
  }
  function floats(b64) {
    if (!b64) return null;
    var bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Float32Array(bytes.buffer);
  }
  function fmt(v, digits) {
    return v === null || v === undefined || !isFinite(v) ? '\u2014' : Number(v).toFixed(digits);
  }
  function sectionColour(section, side) {
    var c = new THREE.Color(SECTION_COLOURS[section] !== undefined ? SECTION_COLOURS[section] : 0xcccccc);
    if (side === 'left') c.lerp(new THREE.Color(0xffffff), 0.35);
    else if (side === 'right') c.lerp(new THREE.Color(0x000000), 0.3);
    return c;
  }

  /* ---- header: title, summary, warnings, notice ---- */
  document.getElementById('title').textContent = data.title || '';
  document.title = 'rigflow report: ' + (data.title || '');
  document.getElementById('summary').textContent = data.summary || '';
  var warnList = document.getElementById('warnings');
  (data.warnings || []).forEach(function (w) { warnList.appendChild(el('li', w)); });
  document.getElementById('notice').textContent = data.notice || '';

  /* ---- timeline ---- */
  var tl = data.timeline;
  var shown = Math.max(1, tl.shown), sampledFps = tl.fps / tl.step;
  var frame = 0, playing = false, speed = 1, clock = 0;

  /* ---- three.js scene ---- */
  var canvas = document.getElementById('view');
  var renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true });
  renderer.setPixelRatio(1);
  renderer.setSize(canvas.clientWidth || 960, canvas.clientHeight || 520, false);
  renderer.setClearColor(0x1e2127);
  var scene = new THREE.Scene();
  var camera = new THREE.PerspectiveCamera(40, (canvas.clientWidth || 960) / (canvas.clientHeight || 520), 0.01, 500);
  camera.position.set(0.2, 1.3, 3.6);
  var controls = new THREE.OrbitControls(camera, canvas);
  controls.target.set(0, 0.45, 0);
  controls.update();
  /* drawn only when something changed: software WebGL on a busy machine has no frames to spare */
  var dirty = true;
  function requestRender() { dirty = true; }
  controls.addEventListener('change', requestRender);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 1.0));
  var sun = new THREE.DirectionalLight(0xffffff, 0.7);
  sun.position.set(2, 4, 3);
  scene.add(sun);
  var grid = new THREE.GridHelper(40, 80, 0x6a7080, 0x3a3f4a);
  scene.add(grid);

  /* The height (along up) drawn on the floor: a source clip's lowest point over the clip (its
   * feet touch its own ground); for the target, its rest pose's lowest point, so a retargeted
   * character that sinks or floats is seen doing so. */
  function floorOf(ch, up) {
    var pts = ch.role === 'source' && ch.anim ? ch.anim : ch.rest, lo = Infinity;
    for (var i = 0; i + 2 < pts.length; i += 3)
      lo = Math.min(lo, up.x * pts[i] + up.y * pts[i + 1] + up.z * pts[i + 2]);
    return isFinite(lo) ? lo : ch.ground;
  }

  /* Each character in a group that puts its up on +Y, its forward on +Z, its height at 1 and its
   * rest on the floor at its slot along X. */
  function displayMatrix(ch, slotX) {
    var up = new THREE.Vector3().fromArray(ch.up).normalize();
    var fw = new THREE.Vector3().fromArray(ch.forward).normalize();
    var left = new THREE.Vector3().crossVectors(up, fw).normalize();
    var k = 1 / (ch.height > 0 ? ch.height : 1);
    var rot = new THREE.Matrix4().set(
      left.x, left.y, left.z, 0, up.x, up.y, up.z, 0, fw.x, fw.y, fw.z, 0, 0, 0, 0, 1);
    /* centred on the first frame shown, so every character starts at its slot */
    var pts = ch.anim || ch.rest, n = ch.np, c = new THREE.Vector3();
    for (var i = 0; i < n; i++) c.add(new THREE.Vector3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]));
    if (n) c.multiplyScalar(1 / n);
    c.applyMatrix4(rot);
    var m = new THREE.Matrix4().makeScale(k, k, k).multiply(rot);
    var t = new THREE.Matrix4().makeTranslation(slotX - c.x * k, -floorOf(ch, up) * k, -c.z * k);
    return t.multiply(m);
  }

  var chars = data.characters.map(function (ch, ci) {
    ch.index = ci;
    ch.rest = Array.prototype.slice.call(floats(ch.rest));
    ch.anim = floats(ch.frames);
    ch.np = ch.rest.length / 3;
    return ch;
  });
  var sources = chars.filter(function (c) { return c.role === 'source'; });
  var target = chars.filter(function (c) { return c.role === 'target'; })[0];
  /* side by side: each character as wide as it is (in its heights, across its facing), apart by 0.4
   * heights, the sources on the left */
  function halfWidth(ch) {
    var up = new THREE.Vector3().fromArray(ch.up).normalize();
    var left = new THREE.Vector3().crossVectors(up, new THREE.Vector3().fromArray(ch.forward).normalize()).normalize();
    var pts = ch.anim || ch.rest, lo = Infinity, hi = -Infinity;
    for (var i = 0; i < ch.np; i++) {
      var d = left.x * pts[3 * i] + left.y * pts[3 * i + 1] + left.z * pts[3 * i + 2];
      lo = Math.min(lo, d); hi = Math.max(hi, d);
    }
    /* the mesh reaches past the joints (wing membranes, hands): a margin */
    var w = isFinite(hi - lo) ? 1.3 * (hi - lo) / 2 / (ch.height > 0 ? ch.height : 1) : 0.5;
    return Math.min(Math.max(w, 0.15), 3);
  }
  var gap = 0.4, x = -gap / 2, span = gap;
  sources.forEach(function (ch) { var w = halfWidth(ch); ch.slot = x - w; x -= 2 * w + gap; span += 2 * w + gap; });
  if (target) { var tw = halfWidth(target); target.slot = sources.length ? gap / 2 + tw : 0; span += 2 * tw; }
  var middle = (x + gap + (target ? target.slot + halfWidth(target) : 0)) / 2;
  camera.position.set(middle + 0.2, 1.3, Math.max(3.2, span * 1.1));
  controls.target.set(middle, 0.45, 0);
  controls.update();

  var sphereGeo = new THREE.SphereBufferGeometry(1, 10, 8);
  var pickables = [];
  chars.forEach(function (ch) {
    var g = new THREE.Group();
    g.matrixAutoUpdate = false;
    g.matrix.copy(displayMatrix(ch, ch.slot));
    scene.add(g);
    ch.group = g;
    var r = 0.012 * (ch.height > 0 ? ch.height : 1);
    ch.spheres = ch.joints.map(function (j, ji) {
      var colour = sectionColour(j.section, j.side);
      var mat = new THREE.MeshBasicMaterial({ color: colour, depthTest: false, transparent: true });
      var s = new THREE.Mesh(sphereGeo, mat);
      s.scale.setScalar(r);
      s.renderOrder = 3;
      s.userData = { ch: ch.index, joint: ji, base: colour.clone(), r: r };
      g.add(s);
      pickables.push(s);
      return s;
    });
    /* bones: parent pivot to pivot, and leaves to their tips */
    var pairs = [];
    ch.joints.forEach(function (j, ji) { if (j.parent >= 0) pairs.push([j.parent, ji, ji]); });
    (ch.tips || []).forEach(function (jt, ti) { pairs.push([jt, ch.joints.length + ti, jt]); });
    ch.pairs = pairs;
    var pos = new Float32Array(pairs.length * 6), col = new Float32Array(pairs.length * 6);
    pairs.forEach(function (p, i) {
      var c = sectionColour(ch.joints[p[2]].section, ch.joints[p[2]].side);
      c.toArray(col, 6 * i); c.toArray(col, 6 * i + 3);
    });
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
    ch.bones = new THREE.LineSegments(geo, new THREE.LineBasicMaterial({
      vertexColors: THREE.VertexColors, depthTest: false, transparent: true }));
    ch.bones.renderOrder = 2;
    ch.bones.frustumCulled = false;
    g.add(ch.bones);
    /* the detected axes, at the rest root: up white, forward cyan */
    var root = new THREE.Vector3().fromArray(ch.rest, 0);
    var len = 0.35 * (ch.height > 0 ? ch.height : 1);
    g.add(new THREE.ArrowHelper(new THREE.Vector3().fromArray(ch.up).normalize(), root, len, 0xffffff));
    g.add(new THREE.ArrowHelper(new THREE.Vector3().fromArray(ch.forward).normalize(), root, len, 0x00e5ff));
  });

  /* ---- mapping lines ---- */
  var links = [];
  var rows = data.mapping ? data.mapping.rows : [];
  rows.forEach(function (row, tj) {
    (row.inputs || []).forEach(function (inp) {
      var src = sources[inp.source];
      if (src && target) links.push({ tj: tj, src: src, sj: inp.joint });
    });
  });
  var linkGeo = new THREE.BufferGeometry();
  linkGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(links.length * 6), 3));
  var linkCol = new Float32Array(links.length * 6);
  linkGeo.setAttribute('color', new THREE.BufferAttribute(linkCol, 3));
  var linkLines = new THREE.LineSegments(linkGeo, new THREE.LineBasicMaterial({
    vertexColors: THREE.VertexColors, transparent: true, opacity: 0.55, depthTest: false }));
  linkLines.frustumCulled = false;
  linkLines.renderOrder = 1;
  scene.add(linkLines);

  /* ---- the target's mesh (exported GLB) ---- */
  var mixer = null, meshRoot = null;
  function ready() { document.body.setAttribute('data-ready', '1'); }
  if (data.glb && target) {
    var bin = atob(data.glb), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    new THREE.GLTFLoader().parse(bytes.buffer, '', function (gltf) {
      meshRoot = new THREE.Group();
      meshRoot.matrixAutoUpdate = false;
      meshRoot.matrix.copy(target.group.matrix);
      meshRoot.add(gltf.scene);
      gltf.scene.traverse(function (o) {
        if (o.isMesh) {
          o.frustumCulled = false;
          o.material.transparent = true;
          o.material.opacity = 0.55;
          o.material.depthWrite = false;
          if (o.material.metalness !== undefined) o.material.metalness = 0;
        }
      });
      scene.add(meshRoot);
      if (gltf.animations && gltf.animations.length) {
        mixer = new THREE.AnimationMixer(gltf.scene);
        mixer.clipAction(gltf.animations[0]).play();
      }
      meshRoot.visible = document.getElementById('mesh').checked;
      setFrame(frame);
      ready();
    }, function (err) {
      warnList.appendChild(el('li', 'the mesh could not be loaded: ' + (err && err.message ? err.message : err)));
      ready();
    });
  }

  /* ---- posing ---- */
  var tmp = new THREE.Vector3();
  function pointOf(ch, k, p, out) {
    var a = ch.anim, base = a ? (k * ch.np + p) * 3 : p * 3;
    return out.set(a ? a[base] : ch.rest[base], a ? a[base + 1] : ch.rest[base + 1], a ? a[base + 2] : ch.rest[base + 2]);
  }
  function contactsAt(k) {
    var on = {};
    var t = k / sampledFps;
    (data.measures || []).forEach(function (m) {
      if (!m.contact || m.joint < 0) return;
      var i = Math.min(m.values.length - 1, Math.round(t * m.fps));
      if (m.values[i] > 0.5) on[m.joint] = true;
    });
    return on;
  }
  var selected = { target: -1, sources: [] };
  function isSelected(ch, j) {
    if (ch === target) return selected.target === j;
    return selected.sources.some(function (s) { return s.src === ch && s.sj === j; });
  }
  function poseAll(k) {
    var contacts = contactsAt(k);
    chars.forEach(function (ch) {
      ch.spheres.forEach(function (s, j) {
        pointOf(ch, k, j, s.position);
        var sel = isSelected(ch, j), touching = ch === target && contacts[j];
        s.material.color.set(sel ? HIGHLIGHT : touching ? CONTACT : s.userData.base);
        s.scale.setScalar(s.userData.r * (sel ? 3.5 : touching ? 2.6 : 1));
      });
      var pos = ch.bones.geometry.attributes.position;
      ch.pairs.forEach(function (p, i) {
        pointOf(ch, k, p[0], tmp); pos.setXYZ(2 * i, tmp.x, tmp.y, tmp.z);
        pointOf(ch, k, p[1], tmp); pos.setXYZ(2 * i + 1, tmp.x, tmp.y, tmp.z);
      });
      pos.needsUpdate = true;
      ch.group.updateMatrixWorld(true);
    });
    var lp = linkGeo.attributes.position, lc = linkGeo.attributes.color;
    var grey = new THREE.Color(0xb0b0b0), hi = new THREE.Color(HIGHLIGHT);
    links.forEach(function (l, i) {
      pointOf(target, k, l.tj, tmp).applyMatrix4(target.group.matrix); lp.setXYZ(2 * i, tmp.x, tmp.y, tmp.z);
      pointOf(l.src, k, l.sj, tmp).applyMatrix4(l.src.group.matrix); lp.setXYZ(2 * i + 1, tmp.x, tmp.y, tmp.z);
      var c = l.tj === selected.target ? hi : grey;
      c.toArray(lc.array, 6 * i); c.toArray(lc.array, 6 * i + 3);
    });
    lp.needsUpdate = true; lc.needsUpdate = true;
    if (mixer) mixer.setTime(k / sampledFps);
    requestRender();
  }

  /* the camera follows the characters' mean root on the floor */
  var lastCentre = null;
  function centre(k) {
    var c = new THREE.Vector3(), n = 0;
    chars.forEach(function (ch) {
      if (!ch.anim) return;
      c.add(pointOf(ch, k, 0, new THREE.Vector3()).applyMatrix4(ch.group.matrix)); n++;
    });
    if (n) c.multiplyScalar(1 / n);
    c.y = 0;
    return c;
  }
  function follow(k) {
    var c = centre(k);
    if (lastCentre && document.getElementById('follow').checked) {
      var d = c.clone().sub(lastCentre);
      camera.position.add(d); controls.target.add(d); controls.update();
    }
    lastCentre = c;
  }

  /* ---- playback controls ---- */
  var scrub = document.getElementById('scrub'), frameLabel = document.getElementById('frame');
  var playButton = document.getElementById('play');
  scrub.max = String(shown - 1);
  function setFrame(k) {
    frame = Math.max(0, Math.min(shown - 1, Math.round(k)));
    clock = frame;
    follow(frame);
    poseAll(frame);
    scrub.value = String(frame);
    var orig = frame * tl.step;
    frameLabel.textContent = 'frame ' + orig + ' / ' + Math.max(0, tl.total - 1) + '  (' + (orig / tl.fps).toFixed(2) + ' s)';
    frameLabel.setAttribute('data-frame', String(orig));
    plots.forEach(function (p) { p.draw(); });
  }
  scrub.addEventListener('input', function () { setFrame(Number(scrub.value)); });
  playButton.addEventListener('click', function () {
    playing = !playing;
    playButton.textContent = playing ? 'Pause' : 'Play';
    last = null;
  });
  document.getElementById('speed').addEventListener('change', function (e) { speed = Number(e.target.value); });
  document.getElementById('lines').addEventListener('change', function (e) { linkLines.visible = e.target.checked; requestRender(); });
  document.getElementById('mesh').addEventListener('change', function (e) { if (meshRoot) meshRoot.visible = e.target.checked; requestRender(); });

  /* ---- the mapping table ---- */
  var table = document.getElementById('mapping');
  var metricNames = data.mapping ? data.mapping.metrics : [];
  var headRow = el('tr');
  ['#', 'target joint', 'section', 'source joint', 'score'].concat(metricNames, ['runner-up'])
    .forEach(function (h) { headRow.appendChild(el('th', h)); });
  table.tHead.appendChild(headRow);
  var rowEls = [];
  if (target) target.joints.forEach(function (j, tj) {
    var row = rows[tj] || { inputs: [] };
    var tr = el('tr');
    tr.setAttribute('data-target', String(tj));
    tr.appendChild(el('td', tj, 'num'));
    tr.appendChild(el('td', j.name));
    var sec = el('td');
    var sw = el('i', null, 'sw');
    sw.style.background = '#' + sectionColour(j.section, j.side).getHexString();
    sec.appendChild(sw);
    sec.appendChild(document.createTextNode((j.section || '?') + (j.side && j.side !== 'center' ? ' ' + j.side : '')));
    tr.appendChild(sec);
    var names = (row.inputs || []).map(function (inp) {
      var src = sources[inp.source];
      var name = src && src.joints[inp.joint] ? src.joints[inp.joint].name : '?';
      var s = (sources.length > 1 ? inp.source + ':' : '') + name;
      if ((row.inputs || []).length > 1) s += ' \u00d7' + fmt(inp.weight, 2);
      if (inp.flags & 1) s += ' (reversed)';
      if (inp.flags & 2) s += ' (mirrored)';
      if (inp.delay) s += ' (' + fmt(inp.delay, 3) + ' s late)';
      return s;
    });
    tr.appendChild(el('td', names.length ? names.join(', ') : 'unmapped'));
    tr.appendChild(el('td', names.length ? fmt(row.score, 1) : '\u2014', 'num'));
    metricNames.forEach(function (_, mi) {
      tr.appendChild(el('td', row.metrics ? fmt(row.metrics[mi], 2) : '\u2014', 'num'));
    });
    tr.appendChild(el('td', row.runner_up ? row.runner_up : '\u2014'));
    if (!names.length) tr.className = 'unmapped';
    tr.addEventListener('click', function () { selectTarget(tj, false); });
    table.tBodies[0].appendChild(tr);
    rowEls.push(tr);
  });
  var picked = document.getElementById('picked');
  function describeSelection(ch, j) {
    picked.textContent = ch ? 'selected: ' + ch.role + ' joint ' + j + ' \u201c' + ch.joints[j].name + '\u201d' +
      ' (' + (ch.joints[j].section || '?') + ' ' + (ch.joints[j].side || '') + ')' : '';
  }
  function selectTarget(tj, scroll) {
    rowEls.forEach(function (r) { r.classList.remove('selected'); });
    selected.target = tj;
    selected.sources = links.filter(function (l) { return l.tj === tj; });
    if (rowEls[tj]) {
      rowEls[tj].classList.add('selected');
      if (scroll) rowEls[tj].scrollIntoView({ block: 'nearest' });
    }
    describeSelection(target, tj);
    poseAll(frame);
  }
  function selectSource(ch, sj) {
    var l = links.filter(function (x) { return x.src === ch && x.sj === sj; })[0];
    if (l) { selectTarget(l.tj, true); return; }
    rowEls.forEach(function (r) { r.classList.remove('selected'); });
    selected.target = -1;
    selected.sources = [{ src: ch, sj: sj }];
    describeSelection(ch, sj);
    picked.textContent += ': drives no target joint';
    poseAll(frame);
  }
  /* the joint under canvas pixel (x, y): {ch, joint}, or null */
  function pick(x, y) {
    var ray = new THREE.Raycaster();
    camera.updateMatrixWorld();
    ray.setFromCamera(new THREE.Vector2(x / canvas.clientWidth * 2 - 1, -y / canvas.clientHeight * 2 + 1), camera);
    var hit = ray.intersectObjects(pickables)[0];
    return hit ? { ch: chars[hit.object.userData.ch], joint: hit.object.userData.joint } : null;
  }
  var down = null;
  canvas.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', function (e) {
    if (!down || Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 4) return;
    var r = canvas.getBoundingClientRect();
    var hit = pick(e.clientX - r.left, e.clientY - r.top);
    if (!hit) return;
    if (hit.ch === target) selectTarget(hit.joint, true); else selectSource(hit.ch, hit.joint);
  });

  /* ---- legend ---- */
  var legend = document.getElementById('legend');
  Object.keys(SECTION_COLOURS).forEach(function (k) {
    var s = el('span'), i = el('i');
    i.style.background = '#' + sectionColour(k, 'center').getHexString();
    s.appendChild(i); s.appendChild(document.createTextNode(k));
    legend.appendChild(s);
  });
  legend.appendChild(el('span', 'left lighter, right darker; white arrow up, cyan arrow forward; red: foot in contact; magenta: selected. ' +
    (sources.length ? 'Source on the left, target on the right.' : '')));

  /* ---- measures over time ---- */
  var plots = [];
  var plotBox = document.getElementById('plots');
  (data.measures || []).forEach(function (m) { m.values = floats(m.values); });
  function seekTime(t) { setFrame(t * sampledFps); }
  (data.measures || []).forEach(function (m) {
    if (m.contact) return;
    var box = el('div', null, 'plot');
    var v = m.values, lo = Infinity, hi = -Infinity, worst = -1, sum = 0, n = 0;
    for (var i = 0; i < v.length; i++) {
      if (!isFinite(v[i])) continue;
      lo = Math.min(lo, v[i]); hi = Math.max(hi, v[i]); sum += v[i]; n++;
      if (worst < 0 || (m.higher_worse ? v[i] > v[worst] : Math.abs(v[i]) > Math.abs(v[worst]))) worst = i;
    }
    var title = m.name + (m.unit ? ' (' + m.unit + ')' : '') + (m.joint >= 0 && target ? ' \u2014 ' + target.joints[m.joint].name : '');
    box.appendChild(el('div', title + (n ? ': mean ' + fmt(sum / n, 3) + ', max ' + fmt(hi, 3) : ': not measured')));
    var c = el('canvas');
    c.width = 360; c.height = 70;
    if (n) box.appendChild(c);
    if (worst >= 0) {
      var b = el('button', 'worst: frame ' + worst + ' (' + fmt(v[worst], 3) + ')');
      b.type = 'button';
      b.addEventListener('click', function () { seekTime(worst / m.fps); });
      box.appendChild(b);
    }
    plotBox.appendChild(box);
    c.addEventListener('click', function (e) {
      var r = c.getBoundingClientRect();
      seekTime((e.clientX - r.left) / r.width * v.length / m.fps);
    });
    var plot = {
      draw: function () {
        var g = c.getContext('2d'), w = c.width, h = c.height;
        g.clearRect(0, 0, w, h);
        if (n) {
          /* from zero (or the lowest value below it), so a steady figure draws a flat line */
          var base = Math.min(lo, 0), span = Math.max(hi, 0) - base || 1;
          g.strokeStyle = '#1a5fb4'; g.beginPath();
          var started = false;
          for (var x = 0; x < w; x++) {
            /* the largest value in the pixel's frames, so no spike is lost */
            var a = Math.floor(x * v.length / w), bnd = Math.max(a + 1, Math.floor((x + 1) * v.length / w)), best = NaN;
            for (var k = a; k < bnd && k < v.length; k++) if (isFinite(v[k]) && !(best >= v[k])) best = v[k];
            if (!isFinite(best)) { started = false; continue; }
            var y = h - 4 - (best - base) / span * (h - 8);
            if (started) g.lineTo(x, y); else { g.moveTo(x, y); started = true; }
          }
          g.stroke();
        }
        var cx = (frame / sampledFps) * m.fps / Math.max(1, v.length) * w;
        g.strokeStyle = '#d00'; g.beginPath(); g.moveTo(cx, 0); g.lineTo(cx, h); g.stroke();
      }
    };
    plots.push(plot);
  });
  /* contacts: one strip per foot */
  var contactSeries = (data.measures || []).filter(function (m) { return m.contact; });
  if (contactSeries.length) {
    var box = el('div', null, 'plot');
    box.appendChild(el('div', 'contacts (a bar where a foot touches the ground)'));
    var c = el('canvas');
    c.width = 360; c.height = 12 * contactSeries.length + 4;
    box.appendChild(c);
    plotBox.appendChild(box);
    var cnames = el('div');
    cnames.textContent = contactSeries.map(function (m) { return target && m.joint >= 0 && target.joints[m.joint] ? target.joints[m.joint].name : '?'; }).join(' / ');
    box.appendChild(cnames);
    plots.push({
      draw: function () {
        var g = c.getContext('2d'), w = c.width;
        g.clearRect(0, 0, w, c.height);
        contactSeries.forEach(function (m, r) {
          g.fillStyle = '#c33';
          for (var x = 0; x < w; x++) {
            var i = Math.floor(x * m.values.length / w);
            if (m.values[i] > 0.5) g.fillRect(x, 2 + 12 * r, 1, 10);
          }
          var cx = (frame / sampledFps) * m.fps / Math.max(1, m.values.length) * w;
          g.fillStyle = '#000'; g.fillRect(cx, 0, 1, c.height);
        });
      }
    });
  }
  if (!plots.length) plotBox.appendChild(el('p', 'No measures reached this report (connect a measuring node such as retarget.measure to its measures input).'));

  /* ---- loop ---- */
  var last = null;
  function tick(now) {
    if (playing) {
      if (last !== null) {
        clock += (now - last) / 1000 * sampledFps * speed;
        if (clock >= shown) clock = 0;
        if (Math.floor(clock) !== frame) { var c = clock; setFrame(Math.floor(c)); clock = c; }
      }
      last = now;
    }
    if (dirty) {
      dirty = false;
      renderer.render(scene, camera);
    }
    requestAnimationFrame(tick);
  }
  setFrame(0);
  window.rigflowReport = {
    frame: function () { return frame * tl.step; },
    shown: shown,
    step: tl.step,
    targetJoints: target ? target.joints.length : 0,
    setFrame: function (k) { setFrame(k); },
    selectTarget: function (j) { selectTarget(j, true); },
    /* canvas pixel of a joint ('source' or 'target'), or null when off screen */
    /* the target joints in contact at shown frame k, from the measures */
    contactsAt: function (k) { return Object.keys(contactsAt(k)).map(Number); },
    /* canvas pixels of the selected joints: {target: [x, y] or null, sources: [[x, y]...]} */
    selectedOnScreen: function () {
      var api = window.rigflowReport;
      return {
        target: selected.target >= 0 ? api.screenOf('target', selected.target) : null,
        sources: selected.sources.map(function (l) { return api.screenOf(l.src, l.sj); })
      };
    },
    screenOf: function (role, j) {
      var ch = role === 'target' ? target : typeof role === 'object' ? role : sources[0];
      if (!ch || !ch.spheres[j]) return null;
      camera.updateMatrixWorld();
      var p = ch.spheres[j].getWorldPosition(new THREE.Vector3()).project(camera);
      if (Math.abs(p.x) > 0.98 || Math.abs(p.y) > 0.98 || p.z > 1) return null;
      return { x: (p.x + 1) / 2 * canvas.clientWidth, y: (1 - p.y) / 2 * canvas.clientHeight };
    },
    /* the target joint under a canvas pixel, or -1 */
    jointAt: function (x, y) {
      var hit = pick(x, y);
      return hit && hit.ch === target ? hit.joint : -1;
    },
    /* the largest distance, in target heights, between a joint drawn and the same-named bone of
     * the embedded mesh at the frame shown: the two views must agree (-1 without a mesh) */
    meshJointError: function () {
      if (!meshRoot || !target) return -1;
      var worst = 0, byName = {};
      meshRoot.updateMatrixWorld(true);
      meshRoot.traverse(function (o) { if (o.isBone) byName[o.name] = o; });
      target.joints.forEach(function (j, ji) {
        var b = byName[THREE.PropertyBinding.sanitizeNodeName(j.name)];
        if (!b) return;
        var p = b.getWorldPosition(new THREE.Vector3());
        var q = pointOf(target, frame, ji, new THREE.Vector3()).applyMatrix4(target.group.matrix);
        worst = Math.max(worst, p.distanceTo(q));
      });
      return worst;
    }
  };
  requestAnimationFrame(tick);
  if (!(data.glb && target)) {
    document.getElementById('mesh').disabled = true;
    ready();
  }
})();
