// nightcrew-client: the hand-written runtime (src/) and the classes generated from the catalogue.
export { NightcrewClient } from "./src/client.js";
export { RemoteInterface } from "./src/remote.js";
export { Event } from "./src/event.js";
export * from "./generated/index.js";
