// Drives a running nightcrew observatory with the generated client only: find the telescope and the
// camera by the interfaces they serve, point, take an image, receive its NewImageEvent, and show
// how bad input fails. Prints one JSON object of what happened (tests/clients/test_js_client.py).
//
// Usage: node observe.mjs '{"jid": ..., "password": ..., "server": "host:port", "room": ..., "timeout": s}'
// (trust a private server's certificate with NODE_EXTRA_CA_CERTS=its.crt).
import {
  ICamera,
  IModule,
  ITelescope,
  NewImageEvent,
  NightcrewClient,
  NightcrewError,
} from "../index.js";

const M39 = [322.95, 48.43];
const options = JSON.parse(process.argv[2]);
const report = { warnings: [] };
const client = new NightcrewClient({ ...options, warn: (message) => report.warnings.push(message) });

/** The first module (by name) serving `Interface`, as disco#info tells. */
async function find(Interface) {
  for (const name of client.modules) {
    if (Interface.spec.name in (await client.interfaces(name))) return name;
  }
  throw new Error(`no module serves ${Interface.spec.name} (online: ${client.modules.join(", ")})`);
}

/** The error a promise fails with, as {class, message}; or {class: null} when it does not fail. */
async function failure(promise) {
  try {
    await promise;
    return { class: null };
  } catch (error) {
    return { class: error.constructor.name, message: error.message, nightcrew: error instanceof NightcrewError };
  }
}

function nextEvent(EventClass, seconds) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no ${EventClass.eventName} within ${seconds} s`)), seconds * 1000);
    const stop = client.on(EventClass, (event, sender) => {
      clearTimeout(timer);
      stop();
      resolve({ event, sender });
    });
  });
}

const intruder = new NightcrewClient({ ...options, password: "not the password" });
report.wrong_password = await failure(intruder.connect(options.timeout));
await intruder.close();

try {
  await client.connect(options.timeout);
  await client.waitUntilReady(options.modules, options.timeout);
  report.modules = {};
  for (const name of client.modules) report.modules[name] = await client.interfaces(name);

  const telescopeName = await find(ITelescope);
  const cameraName = await find(ICamera);
  // Every interface named counts; the proxy also has the methods of the others the module serves.
  const telescope = await client.proxy(telescopeName, ITelescope, IModule);
  const camera = await client.proxy(cameraName, ICamera);
  report.telescope_state = await telescope.get_state();
  report.camera_is_icamera = camera instanceof ICamera;
  report.clock = await client.clock(telescopeName);

  await telescope.init();
  await telescope.move_radec(...M39);
  report.radec = await telescope.get_radec();

  // Longer than a call may take unannounced: grab_data() only succeeds if its announcement counts.
  await camera.set_exposure_time(options.exposure_time); // IExposureTime's, on the ICamera proxy
  const image = nextEvent(NewImageEvent, options.timeout);
  const started = performance.now();
  report.filename = await camera.grab_data();
  report.grab_wall_seconds = (performance.now() - started) / 1000;
  const { event, sender } = await image;
  report.event = { class: event.constructor.name, filename: event.filename, image_type: event.image_type, sender };

  report.bad = {
    wrong_type: await failure(telescope.move_radec("north", 48.43)),
    out_of_range: await failure(telescope.move_radec(322.95, 95)),
    too_many: await failure(telescope.move_radec(322.95, 48.43, 0)),
    below_horizon: await failure(telescope.move_radec(M39[0], -80)),
    unknown_module: await failure(client.proxy("ghost", ITelescope)),
    wrong_interface: await failure(client.proxy(cameraName, ITelescope)),
    wrong_second_interface: await failure(client.proxy(cameraName, ICamera, ITelescope)),
  };
  await telescope.park();
} finally {
  await client.close();
}
process.stdout.write(JSON.stringify(report) + "\n");
