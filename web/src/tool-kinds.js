// The kinds of tool a milling set-up offers: every milling kind of the tool table (core/tools.py ToolKind,
// docs/tools.md; a test keeps this list equal to it). Turning tools belong to the lathe dialects' set-up.
export const MILLING_TOOL_KINDS = ["end_mill", "slot_drill", "ball_nose", "torus", "twist_drill", "spot_drill"];

// The dialects that turn (a blank bar, X as a diameter, feeds per revolution).
export const LATHE_DIALECTS = new Set(["traub-tx8d"]);
