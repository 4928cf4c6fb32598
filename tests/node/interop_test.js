// An independent client flies ardrone-gs's virtual drone: node-ar-drone 0.3.3 (npm `ar-drone`)
// connects to `ardrone-gs sim` over the real ports, receives navdata whose values match what the
// simulator reports, takes off, moves forward, lands, and receives video its PaVE parser accepts.
// Usage: node interop_test.js PATH/TO/ardrone-gs
'use strict';
const assert = require('assert');
const { spawn } = require('child_process');
const arDrone = require('ar-drone');
const PaVEParser = require('ar-drone/lib/video/PaVEParser');

const binary = process.argv[2];
const ip = '127.0.0.2';  // a loopback address of its own: the real, fixed drone ports are free there
const deadline = setTimeout(() => fail(new Error('timed out after 90 s')), 90000);

let sim;
const truth = [];  // the simulator's JSON status lines
function fail(err) {
  console.error('FAIL:', err && err.stack ? err.stack : err);
  if (sim) sim.kill('SIGKILL');
  process.exit(1);
}
process.on('uncaughtException', fail);

function startSim() {
  return new Promise((resolve, reject) => {
    sim = spawn(binary, ['sim', '--bind', ip, '--scenario', 'thesis_open_hall', '--json-status'],
                {stdio: ['ignore', 'pipe', 'inherit']});
    let buf = '';
    sim.stdout.on('data', (d) => {
      buf += d.toString();
      let nl;
      while ((nl = buf.indexOf('\n')) >= 0) {
        const line = buf.slice(0, nl);
        buf = buf.slice(nl + 1);
        if (line.startsWith('virtual AR.Drone 2')) resolve();
        else if (line.startsWith('{')) truth.push(JSON.parse(line));
      }
    });
    sim.on('exit', (code) => reject(new Error('sim exited with ' + code)));
  });
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
function waitFor(pred, ms, what) {
  return new Promise((resolve, reject) => {
    const t0 = Date.now();
    const tick = () => {
      if (pred()) return resolve();
      if (Date.now() - t0 > ms) return reject(new Error('timed out waiting for ' + what));
      setTimeout(tick, 20);
    };
    tick();
  });
}
const latestTruth = () => truth[truth.length - 1];

async function main() {
  await startSim();
  const client = arDrone.createClient({ip: ip});
  const states = [];
  let last = null;
  client.on('navdata', (nd) => {
    if (!nd.demo) return;
    last = nd;
    if (states[states.length - 1] !== nd.demo.controlState) states.push(nd.demo.controlState);
  });

  // Video through node-ar-drone's own PaVE parser.
  const frames = [];
  const parser = new PaVEParser();
  parser.on('data', (f) => frames.push(f));
  parser.on('error', fail);
  client.getVideoStream().on('data', (chunk) => parser.write(chunk));

  await waitFor(() => last !== null && truth.length > 0, 5000, 'demo navdata');
  assert.strictEqual(last.demo.controlState, 'CTRL_LANDED');
  assert.ok(last.droneState.navdataDemo === 1, 'navdata demo bit set');
  assert.ok(Math.abs(last.demo.batteryPercentage - latestTruth().battery_pct) <= 1,
            `battery ${last.demo.batteryPercentage} vs sim ${latestTruth().battery_pct}`);

  await new Promise((resolve) => client.takeoff(resolve));  // resolves on 'hovering'
  await sleep(500);
  const hover = latestTruth();
  assert.strictEqual(hover.ctrl, 'HOVERING');
  // node-ar-drone reports the demo altitude in metres (mm / 1000).
  assert.ok(Math.abs(last.demo.altitudeMeters - hover.z_m) < 0.05,
            `altitude ${last.demo.altitudeMeters} vs sim ${hover.z_m}`);
  assert.strictEqual(last.droneState.flying, 1);

  const x0 = latestTruth().x_m;
  client.front(0.4);
  await sleep(2500);
  assert.strictEqual(last.demo.controlState, 'CTRL_FLYING');
  assert.ok(last.demo.frontBackDegrees < -2, `pitch ${last.demo.frontBackDegrees} (nose down)`);
  assert.ok(last.demo.xVelocity > 300, `vx ${last.demo.xVelocity} mm/s`);
  const moved = latestTruth().x_m - x0;
  assert.ok(moved > 1.0, `moved ${moved} m forward`);
  client.stop();

  await new Promise((resolve) => client.land(resolve));  // resolves on 'landed'
  // The whole flight as the drone reported it (a hover between stop() and land() may be too
  // short to be seen).
  const seen = states;
  assert.deepStrictEqual(seen.slice(0, 4),
                         ['CTRL_LANDED', 'CTRL_TRANS_TAKEOFF', 'CTRL_HOVERING', 'CTRL_FLYING']);
  assert.deepStrictEqual(seen.slice(-2), ['CTRL_TRANS_LANDING', 'CTRL_LANDED']);

  assert.ok(frames.length > 60, `${frames.length} video frames parsed`);
  const f = frames[frames.length - 1];
  assert.strictEqual(f.signature, 'PaVE');
  assert.strictEqual(f.video_codec, 4);
  assert.strictEqual(f.display_width, 640);
  assert.strictEqual(f.display_height, 360);
  assert.ok(frames.some((x) => x.frame_type === 1), 'an IDR frame');
  for (let i = 1; i < frames.length; i++) {
    assert.strictEqual(frames[i].frame_number, frames[i - 1].frame_number + 1, 'frame numbers');
  }
  assert.ok(latestTruth().at_commands > 100, 'the simulator counted the AT stream');

  console.log(`PASS: ${states.length} state changes, ${frames.length} video frames, moved ${moved.toFixed(2)} m`);
  clearTimeout(deadline);
  sim.kill('SIGTERM');
  process.exit(0);
}

main().catch(fail);
