// Marionette as the animation runtime of a three.js page (docs/web.md):
// three's GLTFLoader loads the character for drawing, Marionette gets the same bytes; three's
// bones are bound by their glTF node names through the bridge, and each frame the palette
// (a view on wasm memory) is copied into the bones' world matrices and the morph weights
// into the meshes' influences. A BML box sends blocks; feedback and errors show on the page.
// With WebXR's immersive-ar, the character stands on the hit-tested floor and the viewer
// pose is the scene's "camera".
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadMarionette, PaletteLayout } from 'marionette';

const params = new URLSearchParams(location.search);
const characterFile = params.get('character') || 'RobotExpressive.glb';
const assetBase = params.get('assets') || '/assets/';
const $ = (id) => document.getElementById(id);

const EXAMPLES = {
  gaze: '<bml id="gaze1" characterId="c">\n  <gaze id="g" target="camera" influence="HEAD"/>\n</bml>',
  nod: '<bml id="nod1" characterId="c">\n  <head id="h" lexeme="NOD" repetition="2"/>\n</bml>',
  speech: '<bml id="say1" characterId="c">\n  <speech id="s">\n    <text>He turned sharply, and faced Gregson across the table.</text>\n  </speech>\n  <head id="h" lexeme="NOD" start="s:start+1"/>\n</bml>',
  walk: '<bml id="walk1" characterId="c">\n  <locomotion id="w" target="floorTarget" manner="WALK"/>\n</bml>',
};

const demo = { ready: false, frames: 0, feedback: [], errors: [], visemes: [], morphPeaks: {} };
window.marionetteDemo = demo;

function log(line) {
  const el = $('log');
  el.textContent = `${line}\n${el.textContent}`.slice(0, 6000);
}

async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

// Every bone of the character's skinned meshes, once, with the glTF node name three sanitized.
function collectBones(gltf) {
  const bones = [];
  const seen = new Set();
  gltf.scene.traverse((o) => {
    if (!o.isSkinnedMesh) return;
    o.frustumCulled = false;  // the palette moves it; three's bounds are of the rest pose
    for (const bone of o.skeleton.bones) {
      if (seen.has(bone)) continue;
      seen.add(bone);
      bones.push(bone);
    }
  });
  const nodeName = (bone) => {
    const a = gltf.parser.associations.get(bone);
    const node = a && a.nodes !== undefined ? gltf.parser.json.nodes[a.nodes] : null;
    return node && node.name !== undefined ? node.name : bone.name;
  };
  const index = new Map(bones.map((b, i) => [b, i]));
  return {
    bones,
    names: bones.map(nodeName),
    parents: bones.map((b) => (index.has(b.parent) ? index.get(b.parent) : -1)),
  };
}

// Every morph slot of the character's meshes: the engine's morph slots, by target name. three
// names targets from the mesh's extras.targetNames only; VRM exporters write them on the
// primitive, which three leaves as numbers: those are read from the glTF itself.
function collectMorphs(gltf) {
  const slots = [];
  const json = gltf.parser.json;
  gltf.scene.traverse((o) => {
    if (!o.isMesh || !o.morphTargetDictionary) return;
    const a = gltf.parser.associations.get(o);
    const mesh = a && a.meshes !== undefined ? json.meshes[a.meshes] : null;
    const primitive = mesh && a.primitives !== undefined ? mesh.primitives[a.primitives] : null;
    const names = (mesh && mesh.extras && mesh.extras.targetNames) || (primitive && primitive.extras && primitive.extras.targetNames);
    for (const [key, index] of Object.entries(o.morphTargetDictionary)) {
      slots.push({ mesh: o, index, name: names && names[index] !== undefined ? names[index] : key });
    }
  });
  return slots;
}

async function main() {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(2, window.devicePixelRatio));
  renderer.setSize(window.innerWidth, window.innerHeight);
  $('view').appendChild(renderer.domElement);
  const scene3 = new THREE.Scene();
  scene3.background = new THREE.Color(0x2a2e36);
  const camera = new THREE.PerspectiveCamera(35, window.innerWidth / window.innerHeight, 0.05, 100);
  camera.position.set(0, 1.4, 3.2);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(0, 1.0, 0);
  controls.update();
  scene3.add(new THREE.HemisphereLight(0xffffff, 0x445566, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(2, 4, 3);
  scene3.add(sun);
  const floor = new THREE.Mesh(new THREE.CircleGeometry(6, 48), new THREE.MeshStandardMaterial({ color: 0x3b4250 }));
  floor.rotation.x = -Math.PI / 2;
  scene3.add(floor);
  scene3.add(new THREE.GridHelper(12, 24, 0x556070, 0x445060));
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });

  const startedAt = performance.now();
  const [marionette, bytes] = await Promise.all([loadMarionette(), fetchBytes(assetBase + 'characters/' + characterFile)]);
  const gltf = await new GLTFLoader().parseAsync(bytes.slice().buffer, '');
  // The placement of the character in three's world: identity, or the AR floor anchor.
  const placement = new THREE.Group();
  placement.matrixAutoUpdate = false;
  scene3.add(placement);
  placement.add(gltf.scene);

  const scene = marionette.createScene();
  const asset = marionette.loadAsset(bytes, characterFile);
  const character = scene.addCharacter('c', asset);
  asset.dispose();
  // VRM 0.x characters face -Z (three-vrm turns them too); the camera looks from +Z.
  const json = gltf.parser.json;
  if (json.extensions && json.extensions.VRM && !(json.extensions.VRMC_vrm)) character.setHeading(Math.PI);
  // A character with an idle clip stands in it (without one, it keeps its rest pose).
  const idle = character.clipNames.find((c) => /^idle$/i.test(c));
  if (idle) character.play(idle, 0, { loop: true });
  // Frame the character, whatever its size (RobotExpressive is 4.5 units tall).
  gltf.scene.updateMatrixWorld(true);
  const bounds = new THREE.Box3().setFromObject(gltf.scene);
  const height = Math.max(0.5, bounds.max.y - bounds.min.y);
  controls.target.set(0, bounds.min.y + 0.5 * height, 0);
  camera.position.set(0, bounds.min.y + 0.7 * height, 2.6 * height);
  camera.near = height / 100;
  camera.far = height * 50;
  camera.updateProjectionMatrix();
  controls.update();
  const unit = height / 1.7;  // a person's height, in this character's units
  scene.setObject('floorTarget', 0.8 * unit, 0, 1.2 * unit);
  const skeleton = collectBones(gltf);
  const morphs = collectMorphs(gltf);
  const binding = character.bind({ bones: skeleton.names, parents: skeleton.parents, morphs: morphs.map((m) => m.name) });
  if (binding.report) log(`binding: ${binding.report}`);
  skeleton.bones.forEach((bone, i) => {
    if (binding.jointForBone[i] < 0) return;  // a bone without a joint keeps three's own pose
    bone.matrixAutoUpdate = false;
    bone.matrixWorldAutoUpdate = false;  // written from the palette each frame
  });
  try {
    const [wav, lab] = await Promise.all([fetchBytes(assetBase + 'speech/arctic_a0009.wav'),
      fetchBytes(assetBase + 'speech/arctic_a0009_phone.lab')]);
    scene.addSpeechLine('He turned sharply, and faced Gregson across the table.',
      { audio: wav, audioName: 'arctic_a0009.wav', alignment: lab, alignmentName: 'arctic_a0009_phone.lab' });
  } catch (e) {
    log(`no recorded line: ${e.message}`);
  }

  scene.onFeedback((f) => {
    demo.feedback.push(f);
    log(`${f.sceneTime.toFixed(2)} ${f.kind} ${f.block}${f.behavior ? ':' + f.behavior : ''} ${f.syncPoint}${f.message ? ' ' + f.message : ''}`);
  });
  scene.onViseme((v) => demo.visemes.push(v));
  let audio = null;
  scene.onSpeech((s) => {
    if (!s.samples || typeof AudioContext === 'undefined') return;
    try {
      audio = audio || new AudioContext();
      const buffer = audio.createBuffer(1, s.samples.length, s.sampleRate);
      const data = buffer.getChannelData(0);
      for (let i = 0; i < s.samples.length; ++i) data[i] = s.samples[i] / 32768;
      const source = audio.createBufferSource();
      source.buffer = buffer;
      source.connect(audio.destination);
      source.start(audio.currentTime + Math.max(0, s.startTime - scene.time));
    } catch (e) {
      log(`audio: ${e.message}`);
    }
  });

  function send(text) {
    $('error').textContent = '';
    try {
      scene.sendBml(text);
    } catch (e) {
      demo.errors.push(e.message);
      $('error').textContent = e.message;
    }
  }
  $('bml').value = EXAMPLES.gaze;
  $('send').addEventListener('click', () => send($('bml').value));
  for (const b of document.querySelectorAll('[data-bml]')) {
    b.addEventListener('click', () => { $('bml').value = EXAMPLES[b.dataset.bml]; send(EXAMPLES[b.dataset.bml]); });
  }

  // Clicking the floor sets the walk target.
  const raycaster = new THREE.Raycaster();
  renderer.domElement.addEventListener('dblclick', (event) => {
    const p = new THREE.Vector2((event.clientX / window.innerWidth) * 2 - 1, -(event.clientY / window.innerHeight) * 2 + 1);
    raycaster.setFromCamera(p, camera);
    const hit = raycaster.intersectObject(floor)[0];
    if (!hit) return;
    const local = placement.worldToLocal(hit.point.clone());
    scene.setObject('floorTarget', local.x, 0, local.z);
    send(EXAMPLES.walk.replace('walk1', `walk${Date.now()}`));
  });

  const characterWorld = new THREE.Matrix4();
  const jointModel = new THREE.Matrix4();
  const cameraLocal = new THREE.Vector3();
  let last = performance.now();
  function frame(time, xrFrame) {
    if (xrFrame) placeOnHitTest(xrFrame);
    const dt = Math.min(Math.max((time - last) / 1000, 0), 0.1);  // rAF times may precede the set-up
    last = time;
    // The viewer (the tracked camera in AR) is what "camera" names in BML.
    const viewer = renderer.xr.isPresenting ? renderer.xr.getCamera() : camera;
    viewer.getWorldPosition(cameraLocal);
    placement.worldToLocal(cameraLocal);
    scene.setObject('camera', cameraLocal.x, cameraLocal.y, cameraLocal.z);
    scene.update(dt);
    // Bones: placement * character world * model-space joint matrix (three multiplies in the
    // bone inverses when it skins).
    characterWorld.fromArray(character.worldMatrix()).premultiply(placement.matrixWorld);
    const palette = binding.palette(PaletteLayout.MAT4_COLUMN_MAJOR, false);
    for (let i = 0; i < skeleton.bones.length; ++i) {
      if (binding.jointForBone[i] < 0) continue;  // an engine bone without a joint keeps three's pose
      jointModel.fromArray(palette, i * 16);
      skeleton.bones[i].matrixWorld.multiplyMatrices(characterWorld, jointModel);
    }
    const weights = binding.morphWeights();
    for (let k = 0; k < morphs.length; ++k) {
      if (binding.morphForSlot[k] < 0) continue;
      morphs[k].mesh.morphTargetInfluences[morphs[k].index] = weights[k];
      demo.morphPeaks[morphs[k].name] = Math.max(demo.morphPeaks[morphs[k].name] || 0, weights[k]);
    }
    renderer.render(scene3, camera);
    demo.frames++;
    if (demo.frames === 1) {
      demo.firstFrameMs = performance.now() - startedAt;
      $('status').textContent = `${characterFile}: ${character.jointNames.length} joints, ${morphs.length} morph slots; ` +
        `Marionette ${marionette.version}; first frame after ${demo.firstFrameMs.toFixed(0)} ms`;
    }
  }

  // ---- WebXR immersive-ar: hit-test the floor, place the character there on a tap ----
  let hitTestSource = null;
  let lastHit = null;
  function placeOnHitTest(xrFrame) {
    if (!hitTestSource) return;
    const hits = xrFrame.getHitTestResults(hitTestSource);
    if (hits.length) lastHit = hits[0].getPose(renderer.xr.getReferenceSpace());
  }
  if (navigator.xr && navigator.xr.isSessionSupported) {
    navigator.xr.isSessionSupported('immersive-ar').then((supported) => {
      if (!supported) return;
      $('ar').style.display = 'block';
      $('ar').addEventListener('click', async () => {
        const session = await navigator.xr.requestSession('immersive-ar', { requiredFeatures: ['hit-test'] });
        renderer.xr.enabled = true;
        renderer.xr.setReferenceSpaceType('local');
        await renderer.xr.setSession(session);
        scene3.background = null;
        floor.visible = false;
        const viewerSpace = await session.requestReferenceSpace('viewer');
        hitTestSource = await session.requestHitTestSource({ space: viewerSpace });
        session.addEventListener('select', () => {
          if (!lastHit) return;
          placement.matrix.fromArray(lastHit.transform.matrix);
          placement.updateMatrixWorld(true);
        });
        session.addEventListener('end', () => { hitTestSource = null; renderer.xr.enabled = false; floor.visible = true; });
      });
    });
  }

  // What the browser test reads: the character's box on screen.
  demo.characterScreenBox = () => {
    const box = new THREE.Box3();
    const p = new THREE.Vector3();
    for (const bone of skeleton.bones) box.expandByPoint(p.setFromMatrixPosition(bone.matrixWorld));
    const corners = [];
    for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y]) for (const z of [box.min.z, box.max.z]) {
      corners.push(new THREE.Vector3(x, y, z).project(camera));
    }
    const xs = corners.map((c) => (c.x * 0.5 + 0.5) * window.innerWidth);
    const ys = corners.map((c) => (-c.y * 0.5 + 0.5) * window.innerHeight);
    return { x: Math.min(...xs), y: Math.min(...ys), width: Math.max(...xs) - Math.min(...xs), height: Math.max(...ys) - Math.min(...ys) };
  };
  demo.send = send;
  demo.scene = scene;
  demo.character = character;
  demo.marionette = marionette;
  renderer.setAnimationLoop(frame);
  demo.ready = true;
}

main().catch((e) => {
  $('status').textContent = `failed: ${e.message}`;
  console.error(e);
});
