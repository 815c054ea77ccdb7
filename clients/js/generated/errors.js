// Generated from the nightcrew catalogue by `nightcrew catalogue --js clients/js/generated`.
// Do not edit: change the Python interface, event or error and generate again.

/**
 * Base of all nightcrew errors.
 */
export class NightcrewError extends Error {
  /** @param {string} message */
  constructor(message) {
    super(message);
    this.name = new.target.name;
  }
}

/**
 * An action was aborted on request.
 */
export class AbortedError extends NightcrewError {
}

/**
 * The target was not centred within the allowed attempts.
 */
export class AcquisitionFailedError extends NightcrewError {
}

/**
 * A call that is not valid in the device's state (InvalidOperation, 0x40B), e.g.
 * LastExposureDuration before any exposure.
 */
export class AlpacaInvalidOperationError extends NightcrewError {
}

/**
 * A flat-field light did not reach the state asked for (on and stable, or off).
 */
export class CalibratorError extends NightcrewError {
}

/**
 * A value cannot be encoded for or decoded from the wire.
 */
export class CodecError extends NightcrewError {
}

/**
 * A configuration is invalid.
 */
export class ConfigError extends NightcrewError {
}

/**
 * The device is busy with another action.
 */
export class DeviceBusyError extends NightcrewError {
}

/**
 * No star field near the pointing meets the rules.
 */
export class FocusFieldError extends NightcrewError {
}

/**
 * Taking an image failed.
 */
export class GrabImageError extends NightcrewError {
}

/**
 * Base of all image errors.
 */
export class ImageError extends NightcrewError {
}

/**
 * A module does not offer a required interface, or a method is unknown.
 */
export class InterfaceError extends NightcrewError {
}

/**
 * An argument is out of range or of the wrong kind.
 */
export class InvalidArgumentError extends NightcrewError {
}

/**
 * A module cannot serve a call, e.g. because it is in error state.
 */
export class ModuleError extends NightcrewError {
}

/**
 * A motion (telescope, roof, focuser, ...) failed.
 */
export class MotionError extends NightcrewError {
}

/**
 * The device or module does not support this.
 */
export class NotSupportedError extends NightcrewError {
}

/**
 * A remote call failed; raised as is when the remote error class is not known here.
 */
export class RemoteError extends NightcrewError {
}

/**
 * A step of a script failed; the message names the step and the cause.
 */
export class ScriptError extends NightcrewError {
}

/**
 * The supervisor cannot be reached or refused a request.
 */
export class SupervisorError extends NightcrewError {
}

/**
 * Base of the errors about tasks and task archives.
 */
export class TaskError extends NightcrewError {
}

/**
 * A virtual file system operation failed.
 */
export class VfsError extends NightcrewError {
}

/**
 * The XMPP server refused the login (wrong password, unknown account, no TLS where required).
 */
export class XmppAuthError extends NightcrewError {
}

/**
 * An ``Action`` name the device does not support (ActionNotImplemented, 0x40C).
 */
export class AlpacaActionNotImplementedError extends NotSupportedError {
}

/**
 * The Alpaca server cannot be reached, or it dropped the connection.
 */
export class AlpacaConnectionError extends RemoteError {
}

/**
 * The Alpaca device says it is not connected (0x407); the module reconnects.
 */
export class AlpacaNotConnectedError extends ModuleError {
}

/**
 * A reply that is not valid Alpaca (malformed JSON, missing field, HTTP error, broken image).
 */
export class AlpacaReplyError extends RemoteError {
}

/**
 * A value read before it was ever set (ValueNotSet, 0x402), e.g. TargetRightAscension.
 */
export class AlpacaValueNotSetError extends InvalidArgumentError {
}

/**
 * Base of all plate-solving errors.
 */
export class AstrometryError extends ImageError {
}

/**
 * No room without evicting files that no consumer has fetched yet.
 */
export class CacheFullError extends VfsError {
}

/**
 * No fitting master for a frame, or a master that cannot be used.
 */
export class CalibrationError extends ImageError {
}

/**
 * An expression cannot be parsed, uses something not allowed, or cannot be evaluated.
 */
export class ExpressionError extends InvalidArgumentError {
}

/**
 * A focus series cannot give a best focus (too few good frames, a failed fit).
 */
export class FocusSeriesError extends InvalidArgumentError {
}

/**
 * The caller is not allowed to call this method.
 */
export class ForbiddenError extends RemoteError {
}

/**
 * Pixel data of the wrong kind (dimensions, dtype, size or mismatched shapes).
 */
export class ImageDataError extends ImageError {
}

/**
 * Bytes that cannot be read as, or an image that cannot be written to, FITS.
 */
export class ImageFormatError extends ImageError {
}

/**
 * Initialising a device failed.
 */
export class InitError extends MotionError {
}

/**
 * A request group is invalid.
 */
export class InvalidTaskError extends TaskError {
}

/**
 * A task cannot go from its state to the one asked for (e.g. COMPLETED -> RUNNING).
 */
export class InvalidTransitionError extends TaskError {
}

/**
 * The image has no celestial WCS (or pixel scale), but the operation needs one.
 */
export class MissingWcsError extends ImageError {
}

/**
 * A move failed or was refused.
 */
export class MoveError extends MotionError {
}

/**
 * Too few usable stars in the image for the measurement.
 */
export class NoStarsError extends ImageError {
}

/**
 * A notice that cannot be read (not a VOEvent, no position, coordinates out of range ...).
 */
export class NoticeError extends InvalidArgumentError {
}

/**
 * Parking a device failed.
 */
export class ParkError extends MotionError {
}

/**
 * The portal could not be reached or answered with an error (``status``: HTTP status or 0).
 */
export class PortalError extends TaskError {
}

/**
 * A remote call did not finish within the timeout its callee announced.
 */
export class RemoteTimeoutError extends RemoteError {
}

/**
 * The archive has no task with the given id.
 */
export class TaskNotFoundError extends TaskError {
}

/**
 * A single file is larger than the whole cache.
 */
export class TooLargeError extends VfsError {
}

/**
 * A file or directory does not exist.
 */
export class VfsFileNotFoundError extends VfsError {
}

/**
 * Content cannot be parsed or serialised in the requested format.
 */
export class VfsFormatError extends VfsError {
}

/**
 * A path is malformed or would leave its root.
 */
export class VfsPathError extends VfsError {
}

/**
 * The fitted minimum lies outside the focus range of the series: move the series and retry.
 */
export class FocusOutsideSeriesError extends FocusSeriesError {
}

/**
 * The solver ran but found no solution (too few stars, wrong hints, a field off the catalog).
 */
export class NoSolutionError extends AstrometryError {
}

/**
 * The solver cannot be run: solve-field is not installed, or the service does not answer.
 */
export class SolverUnavailableError extends AstrometryError {
}

/**
 * A path starts with a root name that is not configured.
 */
export class UnknownRootError extends VfsPathError {
}

/** Every error class, by the name a fault's `errorClass` carries. */
export const ERRORS = {AbortedError, AcquisitionFailedError, AlpacaActionNotImplementedError, AlpacaConnectionError, AlpacaInvalidOperationError, AlpacaNotConnectedError, AlpacaReplyError, AlpacaValueNotSetError, AstrometryError, CacheFullError, CalibrationError, CalibratorError, CodecError, ConfigError, DeviceBusyError, ExpressionError, FocusFieldError, FocusOutsideSeriesError, FocusSeriesError, ForbiddenError, GrabImageError, ImageDataError, ImageError, ImageFormatError, InitError, InterfaceError, InvalidArgumentError, InvalidTaskError, InvalidTransitionError, MissingWcsError, ModuleError, MotionError, MoveError, NightcrewError, NoSolutionError, NoStarsError, NotSupportedError, NoticeError, ParkError, PortalError, RemoteError, RemoteTimeoutError, ScriptError, SolverUnavailableError, SupervisorError, TaskError, TaskNotFoundError, TooLargeError, UnknownRootError, VfsError, VfsFileNotFoundError, VfsFormatError, VfsPathError, XmppAuthError};
