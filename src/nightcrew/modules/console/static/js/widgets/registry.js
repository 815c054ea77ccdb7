// Which cards a module page shows: each widget applies when the module offers its interface.

import { acquisitionCard, flatsCard, focusSeriesCard, guidingCard } from "./automation.js";
import { cameraCard } from "./camera.js";
import { filtersCard, focuserCard, motionCard, roofCard } from "./devices.js";
import { imageCard } from "./image.js";
import { mastermindCard, schedulerCard } from "./robotic.js";
import { telescopeCard } from "./telescope.js";
import { weatherCard } from "./weather.js";

const offers = (iface) => (ctx) => ctx.offers(iface);

export const WIDGETS = [
  { applies: offers("IRobotic"), build: mastermindCard },
  { applies: offers("IRoboticScheduler"), build: schedulerCard },
  { applies: offers("ICamera"), build: cameraCard },
  { applies: offers("IData"), build: imageCard },
  { applies: (ctx) => ctx.offers("IPointingRaDec") || ctx.offers("IPointingAltAz"), build: telescopeCard },
  { applies: (ctx) => ctx.offers("IRoof") || ctx.offers("IDome"), build: roofCard },
  { applies: offers("IFocuser"), build: focuserCard },
  { applies: offers("IFilters"), build: filtersCard },
  { applies: offers("IMotion"), build: motionCard },
  { applies: offers("IWeather"), build: weatherCard },
  { applies: offers("IAutoFocus"), build: focusSeriesCard },
  { applies: offers("IAutoGuiding"), build: guidingCard },
  { applies: offers("IFlatField"), build: flatsCard },
  { applies: offers("IAcquisition"), build: acquisitionCard },
];
