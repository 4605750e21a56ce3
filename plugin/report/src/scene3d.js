// The 3D view of redpost's reports (docs/reports.md, "The 3D view"; issue 21).
//
// Every <div class="scene3d"> of the page names its data (a JSON <script>); this script draws the
// cell from the DH chain given there, redoing the forward kinematics of each kept motion (the
// conventions of docs/conventions.md), and moves it with a slider and a play button. It needs
// three.js (global THREE) and its OrbitControls, inlined before it.
//
// For the browser test it exposes window.redpostScenes (one object per view: linkCount(),
// bodyCount(), frameCount, setFrame(k), armScreenBox(), fkErrorMm(), ...) and marks
// <html data-scene-ready="N"> once all N views are built (data-scene-error on a failure).
(function() {
'use strict';

// Anchors of the reports' viridis-like map (svg_draw.cpp): dark (low) to light (high).
var MAP = [
  [68, 1, 84], [72, 40, 120], [62, 73, 137], [49, 104, 142], [38, 130, 142], [31, 158, 137],
  [53, 183, 121], [110, 206, 88], [253, 231, 37]
];
var NONE_RGB = [150, 150, 150];  // a point without a value (a rapid, say)

function mapColour(t) {
  var x = Math.min(Math.max(t, 0), 1) * (MAP.length - 1);
  var i = Math.min(Math.floor(x), MAP.length - 2), f = x - i;
  return [0, 1, 2].map(function(c) { return MAP[i][c] + f * (MAP[i + 1][c] - MAP[i][c]); });
}

// The arrays are little-endian binary in base64: read through DataView, whatever the host.
function bytesOf(b64) {
  var s = atob(b64), u = new Uint8Array(s.length);
  for (var i = 0; i < s.length; i++)
    u[i] = s.charCodeAt(i);
  return u;
}
function floatsOf(b64) {
  var u = bytesOf(b64), dv = new DataView(u.buffer), out = new Float32Array(u.length / 4);
  for (var i = 0; i < out.length; i++)
    out[i] = dv.getFloat32(4 * i, true);
  return out;
}
function uintsOf(b64) {
  var u = bytesOf(b64), dv = new DataView(u.buffer), out = new Uint32Array(u.length / 4);
  for (var i = 0; i < out.length; i++)
    out[i] = dv.getUint32(4 * i, true);
  return out;
}

// Text for innerHTML.
function escapeHtml(t) {
  return String(t).replace(
      /[&<>"]/g,
      function(c) { return {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;'}[c]; });
}

function m34(a) {
  var m = new THREE.Matrix4();
  m.set(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9], a[10], a[11], 0, 0, 0, 1);
  return m;
}

// One DH link at joint value q (rad or mm). Standard: Rz(theta) Tz(d) Tx(a) Rx(alpha);
// modified: Rx(alpha) Tx(a) Rz(theta) Tz(d).
function linkMatrix(L, q, m) {
  var th = L.theta + (L.type === 'prismatic' ? 0 : q), d = L.d + (L.type === 'prismatic' ? q : 0);
  var ct = Math.cos(th), st = Math.sin(th), ca = Math.cos(L.alpha), sa = Math.sin(L.alpha);
  if (L.modified) {
    m.set(
        ct, -st, 0, L.a, st * ca, ct * ca, -sa, -d * sa, st * sa, ct * sa, ca, d * ca, 0, 0, 0, 1);
  } else {
    m.set(
        ct, -st * ca, st * sa, L.a * ct, st, ct * ca, -ct * sa, L.a * st, 0, sa, ca, d, 0, 0, 0, 1);
  }
  return m;
}

// The chain's frames in {B}: before[i] where link i starts (after its fixed transform),
// after[i] where it ends, and the TCP of the tool in force.
function Chain(cell) {
  this.links = cell.links;
  this.T_B_0 = m34(cell.T_B_0);
  this.T_last_tcp = m34(cell.T_last_tcp);
  this.prev = cell.links.map(function(L) { return m34(L.T_prev); });
  this.before = cell.links.map(function() { return new THREE.Matrix4(); });
  this.after = cell.links.map(function() { return new THREE.Matrix4(); });
  this.tcp = new THREE.Matrix4();
  this.tcpChain = new THREE.Matrix4();  // the chain's own TCP (the reference tool)
  this.tmp = new THREE.Matrix4();
}
Chain.prototype.solve = function(q, shift) {
  var F = this.T_B_0;
  for (var i = 0; i < this.links.length; i++) {
    this.before[i].multiplyMatrices(F, this.prev[i]);
    this.after[i].multiplyMatrices(this.before[i], linkMatrix(this.links[i], q[i], this.tmp));
    F = this.after[i];
  }
  this.tcp.multiplyMatrices(F, this.T_last_tcp);
  this.tcpChain.copy(this.tcp);
  // A tool longer than the reference puts its TCP further along -z of the TCP frame.
  this.tcp.multiply(this.tmp.makeTranslation(0, 0, -shift));
};

function origin(m) { return new THREE.Vector3().setFromMatrixPosition(m); }
function column(m, c) { return new THREE.Vector3().setFromMatrixColumn(m, c).normalize(); }

var Y = new THREE.Vector3(0, 1, 0);
// A unit cylinder (along y) or box stretched between two points.
function place(mesh, a, b, radius) {
  var dir = new THREE.Vector3().subVectors(b, a), len = dir.length();
  mesh.visible = len > 1e-6;
  if (!mesh.visible)
    return;
  mesh.position.addVectors(a, b).multiplyScalar(0.5);
  mesh.quaternion.setFromUnitVectors(Y, dir.divideScalar(len));
  mesh.scale.set(radius, len, radius);
}

function View(root, data) {
  var self = this;
  this.root = root;
  this.data = data;
  this.cell = data.cell;
  this.links = data.cell.links;
  this.n = this.links.length;
  this.p = data.cell.positioner_joints;
  this.chain = new Chain(data.cell);
  this.T_B_part = m34(data.cell.T_B_part);
  this.frames = floatsOf(data.frames);
  this.frameMotion = uintsOf(data.frame_motion);
  this.frameLine = uintsOf(data.frame_line);
  this.stride = this.n + 5;
  this.frameCount = this.frameMotion.length;
  this.path = floatsOf(data.path);
  this.pathMotion = uintsOf(data.path_motion);
  this.codes = data.path_values.map(bytesOf);
  this.expectedLinks = this.n;
  this.frame = 0;
  this.q = new Float64Array(this.n);

  this.scene = new THREE.Scene();
  this.scene.background = new THREE.Color(0xf7f7f7);
  this.scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 0.75));
  var sun = new THREE.DirectionalLight(0xffffff, 0.55);
  sun.position.set(1, -2, 3);
  this.scene.add(sun);
  this.floorFrame = new THREE.Group();  // the cell's fixed parts, in the floor frame
  this.scene.add(this.floorFrame);
  this.tableFrame = new THREE.Group();  // {B}: the table, the workpiece and its toolpath
  this.tableFrame.matrixAutoUpdate = false;
  this.scene.add(this.tableFrame);
  this.F0 = new THREE.Matrix4();
  if (this.p > 0) {
    this.chain.solve(new Float64Array(this.n), 0);
    this.F0.copy(this.chain.after[this.p - 1]);
  }
  this.buildLinks();
  this.buildTable();
  this.buildBodies();
  this.solve(0);
  this.updateLinks();
  this.buildFloor();

  this.webgl = View.hasWebGL();
  this.canvas = root.querySelector('canvas');
  this.slider = root.querySelector('input.s3-slider');
  this.slider.max = String(this.frameCount - 1);
  this.readout = root.querySelector('.s3-readout');
  this.select = root.querySelector('select.s3-quantity');
  this.playButton = root.querySelector('button.s3-play');
  this.slider.addEventListener('input', function() { self.setFrame(+self.slider.value); });
  this.select.addEventListener('change', function() { self.colourPath(+self.select.value); });
  this.playButton.addEventListener('click', function() { self.togglePlay(); });
  this.colourPath(0);
  if (!this.webgl) {
    root.querySelector('.s3-msg').textContent =
        'This browser gives the page no WebGL, so the 3D view cannot be drawn ' +
        '(the rest of the report is not affected).';
    this.canvas.style.display = 'none';
    this.showReadout();
    return;
  }
  this.renderer =
      new THREE.WebGLRenderer({canvas: this.canvas, antialias: true, preserveDrawingBuffer: true});
  var w = Math.min(root.clientWidth || 1240, 1240), h = Math.round(w * 0.5);
  this.renderer.setPixelRatio(window.devicePixelRatio || 1);
  this.renderer.setSize(w, h);
  this.camera = new THREE.PerspectiveCamera(35, w / h, 10, 1e6);
  this.camera.up.set(0, 0, 1);
  this.fitCamera();
  this.controls = new THREE.OrbitControls(this.camera, this.canvas);
  this.controls.target.copy(this.centre);
  this.controls.update();
  this.controls.addEventListener('change', function() { self.render(); });
  this.setFrame(0);
}

View.hasWebGL = function() {
  try {
    var c = document.createElement('canvas');
    return !!(
        window.WebGLRenderingContext &&
        (c.getContext('webgl') || c.getContext('experimental-webgl')));
  } catch (e) {
    return false;
  }
};

// Sizes from the arm's own lengths: bones about 3.5 % of its longest link.
View.prototype.sizes = function() {
  var longest = 0;
  for (var i = this.p; i < this.n; i++) {
    var L = this.links[i];
    if (L.type === 'revolute')
      longest = Math.max(longest, Math.abs(L.a) + Math.abs(L.d));
  }
  var bone = Math.min(Math.max(0.035 * longest, 12), 120);
  return {bone: bone, joint: 1.6 * bone, tool: Math.max(0.25 * bone, 4)};
};

View.prototype.buildLinks = function() {
  var cyl = new THREE.CylinderBufferGeometry(1, 1, 1, 20);
  var box = new THREE.BoxBufferGeometry(1, 1, 1);
  var arm = new THREE.MeshLambertMaterial({color: 0xf08a00});
  var joint = new THREE.MeshLambertMaterial({color: 0x444444});
  var track = new THREE.MeshLambertMaterial({color: 0x7a7f87});
  var tool = new THREE.MeshLambertMaterial({color: 0xc9ccd1});
  var spindle = new THREE.MeshLambertMaterial({color: 0x2f4f6f});
  this.size = this.sizes();
  this.linkGroups = [];
  for (var i = 0; i < this.n; i++) {
    var L = this.links[i], g = new THREE.Group(), positioner = i < this.p;
    g.name = 'link:' + L.name;
    g.userData.link = true;  // counted by linkCount() (a name may be empty)
    g.userData.linkName = L.name;
    g.userData.arm = !positioner;
    // A track's moving part is drawn by its rail and carriage: its bones in the rail's grey.
    var m = positioner || L.type === 'prismatic' ? track : L.type === 'virtual' ? spindle : arm;
    // The link's two DH moves (along z and along x), and the fixed transform before it (a
    // spindle mount, say) as a third.
    g.userData.bones = [
      new THREE.Mesh(cyl, m), new THREE.Mesh(cyl, m),
      new THREE.Mesh(cyl, L.type === 'virtual' ? spindle : m)
    ];
    g.userData.housing =
        new THREE.Mesh(L.type === 'prismatic' ? box : cyl, L.type === 'prismatic' ? track : joint);
    g.add(g.userData.bones[0], g.userData.bones[1], g.userData.bones[2], g.userData.housing);
    if (i === this.n - 1) {
      // The chain's last frame to its TCP (the cell's <tool> transform).
      g.userData.tcpBone = new THREE.Mesh(cyl, spindle);
      g.add(g.userData.tcpBone);
    }
    if (L.type === 'prismatic') {
      g.userData.rail = new THREE.Mesh(box, track);
      g.add(g.userData.rail);
    }
    if (L.type === 'virtual') {
      g.userData.tool = new THREE.Mesh(cyl, tool);
      g.add(g.userData.tool);
    }
    (positioner ? this.floorFrame : this.scene).add(g);
    this.linkGroups.push(g);
  }
};

View.prototype.frameAt = function(k) {
  return this.frames.subarray(k * this.stride, (k + 1) * this.stride);
};

// The chain at frame k. The floor is {B} with the positioner (the table) at zero: a point
// fixed to the robot's side of the chain is drawn at F(0) F(q)^-1 times its place in {B},
// where F(q) is the frame after the positioner joints, and the table turns under the robot.
View.prototype.solve = function(k) {
  var f = this.frameAt(k);
  for (var i = 0; i < this.n; i++)
    this.q[i] = f[i];
  this.toolLength = f[this.n];
  this.chain.solve(this.q, f[this.n + 1]);
  this.W_inv = new THREE.Matrix4();
  if (this.p > 0) {
    this.W_inv.getInverse(this.chain.after[this.p - 1]);
    this.W_inv.premultiply(this.F0);
  }
};

View.prototype.world = function(m) {
  return new THREE.Matrix4().multiplyMatrices(this.W_inv, m);
};

View.prototype.updateLinks = function() {
  var s = this.size;
  this.armPoints = [];
  for (var i = 0; i < this.n; i++) {
    var L = this.links[i], g = this.linkGroups[i];
    var B = this.world(this.chain.before[i]), A = this.world(this.chain.after[i]);
    var o0 = origin(B), o1 = origin(A), mid, axis, at;
    var dq = L.type === 'prismatic' ? this.q[i] : 0;
    if (L.modified) {
      mid = o0.clone().addScaledVector(column(B, 0), L.a);
      axis = column(A, 2);
      at = mid;
    } else {
      mid = o0.clone().addScaledVector(column(B, 2), L.d + dq);
      axis = column(B, 2);
      at = o0;
    }
    var r = i < this.p ? 0.6 * s.bone : L.type === 'virtual' ? 0.5 * s.bone : s.bone;
    place(g.userData.bones[0], o0, mid, r);
    place(g.userData.bones[1], mid, o1, r);
    var start = origin(this.world(i > 0 ? this.chain.after[i - 1] : this.chain.T_B_0));
    place(g.userData.bones[2], start, o0, L.type === 'virtual' ? 1.4 * s.bone : r);
    if (g.userData.tcpBone)
      place(g.userData.tcpBone, o1, origin(this.world(this.chain.tcpChain)), 0.6 * s.bone);
    var h = g.userData.housing;
    if (L.type === 'prismatic') {
      // The rail over the joint's whole range, the carriage where the joint is.
      var base = L.modified ? mid.clone().addScaledVector(axis, -(L.d + dq)) : o0;
      place(
          g.userData.rail, base.clone().addScaledVector(axis, L.d + L.lower),
          base.clone().addScaledVector(axis, L.d + L.upper), 0.8 * s.bone);
      var carriage = L.modified ? o1 : mid;
      place(
          h, carriage.clone().addScaledVector(axis, -1.5 * s.joint),
          carriage.clone().addScaledVector(axis, 1.5 * s.joint), 2 * s.joint);
    } else if (L.type === 'revolute') {
      place(
          h, at.clone().addScaledVector(axis, -0.8 * s.joint),
          at.clone().addScaledVector(axis, 0.8 * s.joint), s.joint);
    } else {
      h.visible = false;
    }
    if (g.userData.tool) {
      // The tool: from its tip (the TCP in force) back along the tool axis by its length.
      var T = this.world(this.chain.tcp), tip = origin(T), up = column(T, 2);
      // Of unknown length, the tool is the chain itself up to the TCP: nothing more is drawn.
      var len = isFinite(this.toolLength) && this.toolLength > 0 ? this.toolLength : 0;
      place(g.userData.tool, tip, tip.clone().addScaledVector(up, len), s.tool);
      this.tip = tip;
    }
    if (i >= this.p)
      this.armPoints.push(o0, mid, o1);
  }
  if (this.tip)
    this.armPoints.push(this.tip);
  this.tableFrame.matrix.copy(this.W_inv);
  this.tableFrame.matrixWorldNeedsUpdate = true;
  this.updateBodies();
};

// The bodies of the collision check (docs/collision.md), translucent: the cell's (orange), the
// tool's (grey), the fixtures (brown) and the part (green). Those on {B} are drawn in the table's
// frame; the others follow their link, or the TCP, frame by frame (updateBodies). The closest
// approach of the program is a red line between its two nearest points.
View.prototype.buildBodies = function() {
  var colours = {cell: 0xf0a040, tool: 0x9aa0a8, fixture: 0x8b5a2b, part: 0x3c9a5f};
  var self = this;
  this.bodyGroups = [];
  (this.data.bodies || []).forEach(function(b) {
    var g = new THREE.Group(), mat = new THREE.MeshLambertMaterial({
      color: colours[b.role] || 0x888888,
      transparent: true,
      opacity: b.role === 'part' || b.role === 'fixture' ? 0.45 : 0.28,
      depthWrite: false
    });
    g.userData.body = b.name;  // not a link: scene_check.py counts those apart
    g.userData.frame = b.frame;
    g.matrixAutoUpdate = false;
    b.shapes.forEach(function(s) {
      var T = m34(s.T);
      var add = function(geometry, local) {
        var mesh = new THREE.Mesh(geometry, mat);
        mesh.matrixAutoUpdate = false;
        mesh.matrix.multiplyMatrices(T, local || new THREE.Matrix4());
        g.add(mesh);
      };
      // three.js's cylinders stand on y; ours lie on z.
      var onZ = new THREE.Matrix4().makeRotationX(Math.PI / 2);
      if (s.kind === 'sphere') {
        add(new THREE.SphereBufferGeometry(s.radius, 20, 14));
      } else if (s.kind === 'box') {
        add(new THREE.BoxBufferGeometry(s.size[0], s.size[1], s.size[2]));
      } else if (s.kind === 'cylinder' || s.kind === 'capsule') {
        add(new THREE.CylinderBufferGeometry(s.radius, s.radius, s.length, 24), onZ);
        if (s.kind === 'capsule') {
          [-0.5, 0.5].forEach(function(end) {
            add(new THREE.SphereBufferGeometry(s.radius, 20, 14),
                new THREE.Matrix4().makeTranslation(0, 0, end * s.length));
          });
        }
      } else if (s.kind === 'mesh') {
        var geo = new THREE.BufferGeometry();
        geo.setAttribute('position', new THREE.Float32BufferAttribute(floatsOf(s.vertices), 3));
        geo.setIndex(Array.prototype.slice.call(uintsOf(s.triangles)));
        geo.computeVertexNormals();
        add(geo);
      }
    });
    (b.frame === -1 ? self.tableFrame : self.scene).add(g);
    self.bodyGroups.push(g);
  });
  if (this.data.closest) {
    var c = this.data.closest, a = new THREE.Vector3().fromArray(c.a).applyMatrix4(this.T_B_part);
    var e = new THREE.Vector3().fromArray(c.b).applyMatrix4(this.T_B_part);
    var red = new THREE.MeshBasicMaterial({color: 0xd62728});
    this.closestLine = new THREE.Line(
        new THREE.BufferGeometry().setFromPoints([a, e]),
        new THREE.LineBasicMaterial({color: 0xd62728}));
    this.tableFrame.add(this.closestLine);
    [a, e].forEach(function(p) {
      var dot = new THREE.Mesh(new THREE.SphereBufferGeometry(4, 12, 8), red);
      dot.position.copy(p);
      self.tableFrame.add(dot);
    });
  }
};

// Each body on a link (or the TCP) at the frame shown.
View.prototype.updateBodies = function() {
  var self = this;
  (this.bodyGroups || []).forEach(function(g) {
    var f = g.userData.frame;
    if (f === -1)
      return;  // in the table's frame already
    g.matrix.copy(self.world(f === -2 ? self.chain.tcp : self.chain.after[f]));
    g.matrixWorldNeedsUpdate = true;
  });
};

// The table under the workpiece: a disc on a turntable ({B} turns with it), a slab otherwise;
// its top level with the lowest toolpath point (or z = 0 of {B}, whichever is lower).
View.prototype.buildTable = function() {
  var pts = [], lo = new THREE.Vector3(Infinity, Infinity, Infinity);
  var hi = new THREE.Vector3(-Infinity, -Infinity, -Infinity), radius = 0;
  for (var i = 0; i < this.path.length; i += 3) {
    var v = new THREE.Vector3(this.path[i], this.path[i + 1], this.path[i + 2])
                .applyMatrix4(this.T_B_part);
    pts.push(v.x, v.y, v.z);
    lo.min(v);
    hi.max(v);
    radius = Math.max(radius, Math.hypot(v.x, v.y));
  }
  if (!pts.length)
    lo.set(0, 0, 0), hi.set(0, 0, 0);
  var geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
  geo.setAttribute('color', new THREE.Float32BufferAttribute(new Float32Array(pts.length), 3));
  // Measurement points are points; a toolpath is a line.
  this.pathLine = this.data.path_as_points ?
      new THREE.Points(
          geo,
          new THREE.PointsMaterial(
              {vertexColors: THREE.VertexColors, size: 7, sizeAttenuation: false})) :
      new THREE.Line(geo, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors}));
  this.tableFrame.add(this.pathLine);
  var self = this;
  (this.data.rects || []).forEach(function(r) {
    var c = new THREE.Vector3().fromArray(r.corner), u = new THREE.Vector3().fromArray(r.u);
    var v = new THREE.Vector3().fromArray(r.v),
        quad = [c, c.clone().add(u), c.clone().add(u).add(v), c.clone().add(v)];
    quad = quad.map(function(p) { return p.applyMatrix4(self.T_B_part); });
    var g = new THREE.BufferGeometry().setFromPoints(
        [quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
    self.tableFrame.add(new THREE.Mesh(g, new THREE.MeshBasicMaterial({
      color: r.colour,
      transparent: true,
      opacity: 0.22,
      side: THREE.DoubleSide,
      depthWrite: false
    })));
    self.tableFrame.add(new THREE.LineLoop(
        new THREE.BufferGeometry().setFromPoints(quad),
        new THREE.LineBasicMaterial({color: r.colour})));
    quad.forEach(function(p) {
      lo.min(p);
      hi.max(p);
    });
  });
  var top = this.p > 0 ? Math.min(0, lo.z) : lo.z, thick = 40, mesh;
  var mat = new THREE.MeshLambertMaterial({color: 0xb8bcc2, transparent: true, opacity: 0.85});
  if (this.p > 0) {
    mesh = new THREE.Mesh(new THREE.CylinderBufferGeometry(1, 1, 1, 64), mat);
    place(
        mesh, new THREE.Vector3(0, 0, top - thick - 1), new THREE.Vector3(0, 0, top - 1),
        radius + 60);
  } else {
    mesh = new THREE.Mesh(new THREE.BoxBufferGeometry(1, 1, 1), mat);
    mesh.position.set((lo.x + hi.x) / 2, (lo.y + hi.y) / 2, top - thick / 2 - 1);
    mesh.scale.set(hi.x - lo.x + 120, hi.y - lo.y + 120, thick);
  }
  this.tableFrame.add(mesh);
  this.marker = new THREE.Mesh(
      new THREE.SphereBufferGeometry(1, 16, 12), new THREE.MeshBasicMaterial({color: 0xd62728}));
  this.tableFrame.add(this.marker);
  this.tableLow = top - thick;
};

View.prototype.buildFloor = function() {
  var box = new THREE.Box3().setFromObject(this.scene);
  box.expandByPoint(new THREE.Vector3(0, 0, this.tableLow));
  var size = box.getSize(new THREE.Vector3()), span = Math.max(size.x, size.y) * 1.6;
  var step = Math.pow(10, Math.floor(Math.log10(span / 10)));
  var grid = new THREE.GridHelper(
      Math.ceil(span / step) * step, Math.ceil(span / step), 0xbbbbbb, 0xdddddd);
  grid.rotation.x = Math.PI / 2;  // three.js grids lie in x-z; the cell's floor is x-y
  grid.position.set((box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2, box.min.z - 1);
  this.floorFrame.add(grid);
  if (this.p === 0) {
    // The robot stands on {B}: a pedestal from the floor up to its first frame.
    var base = origin(this.chain.T_B_0),
        pedestal = new THREE.Mesh(
            new THREE.CylinderBufferGeometry(1, 1, 1, 24),
            new THREE.MeshLambertMaterial({color: 0x7a7f87}));
    place(pedestal, new THREE.Vector3(base.x, base.y, box.min.z - 1), base, 2.2 * this.size.bone);
    this.floorFrame.add(pedestal);
  }
  // The camera frames the arm at the first motion and the toolpath: a long track's rail or a
  // large table would leave them small.
  var focus = new THREE.Box3().setFromObject(this.pathLine);
  // The arm over up to 40 of the kept motions, so that no motion leaves the view.
  var step = Math.max(1, Math.floor(this.frameCount / 40));
  for (var k = 0; k < this.frameCount; k += step) {
    this.solve(k);
    this.updateLinks();
    this.armPoints.forEach(function(p) { focus.expandByPoint(p); });
  }
  this.solve(0);
  this.updateLinks();
  this.focus = focus;
  this.centre = focus.getCenter(new THREE.Vector3());
  this.extent = focus.getSize(new THREE.Vector3()).length();
};

// From a fixed direction (front right, above), the distance at which the focus box's corners
// fill about 90 % of the view: a few steps of scaling the distance by how far the corners
// reach (their screen positions shrink about as 1 / distance).
View.prototype.fitCamera = function() {
  var dir = new THREE.Vector3(0.55, -0.75, 0.45).normalize(), b = this.focus, corners = [];
  for (var k = 0; k < 8; k++) {
    corners.push(new THREE.Vector3(
        k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z));
  }
  var d = this.extent / (2 * Math.tan((this.camera.fov * Math.PI) / 360));
  for (var it = 0; it < 4; it++) {
    this.camera.position.copy(this.centre).addScaledVector(dir, d);
    this.camera.lookAt(this.centre);
    this.camera.updateMatrixWorld();
    var reach = 0, cam = this.camera;
    corners.forEach(function(c) {
      var v = c.clone().project(cam);
      reach = Math.max(reach, Math.abs(v.x), Math.abs(v.y));
    });
    d *= Math.max(reach / 0.9, 0.5);
  }
  this.camera.position.copy(this.centre).addScaledVector(dir, d);
  this.camera.lookAt(this.centre);
};

View.prototype.colourPath = function(qi) {
  var Q = this.data.quantities[qi], codes = this.codes[qi];
  var col = this.pathLine.geometry.getAttribute('color');
  for (var i = 0; i < this.pathMotion.length; i++) {
    var c = Q && codes[i] !== 255 ? mapColour(codes[i] / 254) : NONE_RGB;
    col.setXYZ(i, c[0] / 255, c[1] / 255, c[2] / 255);
  }
  col.needsUpdate = true;
  var bar = this.root.querySelector('.s3-bar');
  if (Q) {
    var stops = MAP.map(function(
        c,
        j) { return 'rgb(' + c.join(',') + ') ' + (100 * j / (MAP.length - 1)).toFixed(1) + '%'; });
    var unit = Q.unit ? ' ' + escapeHtml(Q.unit) : '';
    var mark = '';
    if (Q.threshold !== null && Q.hi > Q.lo) {
      var t = (Q.threshold - Q.lo) / (Q.hi - Q.lo);
      if (t >= 0 && t <= 1)
        mark = '<i style="left:' + (100 * t).toFixed(1) + '%" title="' +
            escapeHtml(Q.threshold_name) + '"></i>';
    }
    bar.innerHTML = '<b>' + Q.lo.toPrecision(3) + unit +
        '</b><span style="background:linear-gradient(to right,' + stops.join(',') + ')">' + mark +
        '</span><b>' + Q.hi.toPrecision(3) + unit + '</b> ' +
        (Q.categorical ? '' :
                         (Q.higher_is_better ? '(higher is better' : '(lower is better') +
                 (Q.threshold !== null ? '; the mark: ' + escapeHtml(Q.threshold_name) + ' ' +
                          Q.threshold.toPrecision(3) + unit :
                                         '') +
                 ')');
  }
  this.render();
};

View.prototype.showReadout = function() {
  var f = this.frameAt(this.frame), parts = [];
  for (var i = 0; i < this.n; i++) {
    var L = this.links[i];
    if (!L.axis_sign)
      continue;
    var v = L.axis_sign * (L.type === 'prismatic' ? f[i] : f[i] * 180 / Math.PI) + L.axis_offset;
    parts.push(L.axis + ' ' + v.toFixed(1) + (L.type === 'prismatic' ? ' mm' : '\u00b0'));
  }
  this.readout.textContent = 'motion ' + this.frameMotion[this.frame] + ' of ' + this.data.motions +
      ' (' + this.data.line_label + ' ' + this.frameLine[this.frame] + '): ' + parts.join('  ');
};

View.prototype.setFrame = function(k) {
  this.frame = Math.max(0, Math.min(this.frameCount - 1, Math.round(k)));
  this.slider.value = String(this.frame);
  this.solve(this.frame);
  this.updateLinks();
  var f = this.frameAt(this.frame);
  var tcp =
      new THREE.Vector3(f[this.n + 2], f[this.n + 3], f[this.n + 4]).applyMatrix4(this.T_B_part);
  this.marker.position.copy(tcp);
  this.marker.scale.setScalar(0.6 * this.size.bone);
  this.showReadout();
  this.render();
};

View.prototype.render = function() {
  if (this.renderer)
    this.renderer.render(this.scene, this.camera);
};

// Plays the kept motions in about 20 s, whatever their number.
View.prototype.togglePlay = function() {
  var self = this;
  this.playing = !this.playing;
  this.playButton.textContent = this.playing ? 'Pause' : 'Play';
  if (!this.playing)
    return;
  if (this.frame >= this.frameCount - 1)
    this.setFrame(0);
  var step = Math.max(1, this.frameCount / 1200), at = this.frame;
  function tick() {
    if (!self.playing)
      return;
    at = Math.min(self.frameCount - 1, at + step);
    self.setFrame(at);
    if (self.frame >= self.frameCount - 1)
      return self.togglePlay();
    requestAnimationFrame(tick);
  }
  requestAnimationFrame(tick);
};

// --- for the browser test -----------------------------------------------------------------

View.prototype.linkCount = function() {
  var count = 0;
  this.scene.traverse(function(o) {
    if (o.userData.link)
      count++;
  });
  return count;
};

// The bodies of the collision check in the scene (one group each, userData.body).
View.prototype.bodyCount = function() {
  var count = 0;
  this.scene.traverse(function(o) {
    if (o.userData.body)
      count++;
  });
  return count;
};

// The largest distance (mm) between this page's TCP and the host's over the kept motions.
View.prototype.fkErrorMm = function() {
  var worst = 0, part_B = new THREE.Matrix4().getInverse(this.T_B_part);
  for (var k = 0; k < this.frameCount; k++) {
    var f = this.frameAt(k);
    for (var i = 0; i < this.n; i++)
      this.q[i] = f[i];
    this.chain.solve(this.q, f[this.n + 1]);
    var p = origin(this.chain.tcp).applyMatrix4(part_B);
    worst = Math.max(
        worst, p.distanceTo(new THREE.Vector3(f[this.n + 2], f[this.n + 3], f[this.n + 4])));
  }
  this.solve(this.frame);
  return worst;
};

// Where the arm (the links past the positioner, the tool included) is on the screen, in CSS
// pixels of the viewport.
View.prototype.armScreenBox = function() {
  var rect = this.canvas.getBoundingClientRect(),
      box = {x0: Infinity, y0: Infinity, x1: -Infinity, y1: -Infinity};
  var cam = this.camera;
  this.armPoints.forEach(function(p) {
    var v = p.clone().project(cam);
    var x = rect.left + (v.x + 1) / 2 * rect.width, y = rect.top + (1 - v.y) / 2 * rect.height;
    box.x0 = Math.min(box.x0, x);
    box.x1 = Math.max(box.x1, x);
    box.y0 = Math.min(box.y0, y);
    box.y1 = Math.max(box.y1, y);
  });
  return box;
};

View.prototype.api = function() {
  var v = this;
  return {
    id: v.root.id,
    webgl: v.webgl,
    canvas: v.canvas,
    slider: v.slider,
    frameCount: v.frameCount,
    expectedLinks: v.expectedLinks,
    linkCount: function() { return v.linkCount(); },
    bodyCount: function() { return v.bodyCount(); },
    setFrame: function(k) { v.setFrame(k); },
    armScreenBox: function() { return v.armScreenBox(); },
    fkErrorMm: function() { return v.fkErrorMm(); }
  };
};

var views = document.querySelectorAll('div.scene3d');
window.redpostScenes = [];
try {
  for (var i = 0; i < views.length; i++) {
    var data = JSON.parse(document.getElementById(views[i].dataset.scene).textContent);
    window.redpostScenes.push(new View(views[i], data).api());
  }
  document.documentElement.setAttribute('data-scene-ready', String(views.length));
} catch (e) {
  document.documentElement.setAttribute('data-scene-error', String(e && e.stack || e));
  throw e;
}
})();
