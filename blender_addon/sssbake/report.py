"""What a bake tells the artist, read from the library's summary (docs/outputs.md, "The summary"):
per object the method, why it was chosen, its estimated error against the exact sum and
against light, and the seconds per stage;
and progress as plain lines for a log when Blender runs in the background."""

import sys


def object_line(planned):
    """One line for one baked object of the summary."""
    parts = [planned["name"]]
    integrator = planned.get("integrator")
    accuracy = planned.get("accuracy")
    if integrator:
        parts.append(f"{integrator['method']} ({integrator['reason']})")
    else:
        parts.append("no scattering")
    if accuracy:
        if accuracy.get("method") and integrator and accuracy["method"] != integrator["method"]:
            parts.append(f"the maps hold {accuracy['method']}")
        parts.append(f"estimated error {100 * accuracy['estimated_error']:.2g}%")
        light = accuracy.get("light")
        if light:
            parts.append(
                f"against light {100 * light['estimated_error']:.2g}%"
                f" (a random walk at {light['texels']} texels, its noise {100 * light['walk_noise']:.2g}%)"
            )
        elif accuracy.get("light_unchecked"):
            parts.append(f"against light: not checked ({accuracy['light_unchecked']})")
    seconds = planned.get("seconds") or {}
    if seconds:
        stages = ", ".join(f"{stage} {value:.2f} s" for stage, value in seconds.items())
        parts.append(stages)
    return "; ".join(parts)


class ProgressLines:
    """Progress printed as `sssbake: <object> <percent>%` lines for logs without a status
    bar: an object's first report, then each `step` percent more, and its end."""

    def __init__(self, step=10, stream=None):
        self.step = step
        self.stream = stream or sys.stdout
        self.last = (None, -1)

    def __call__(self, name, fraction):
        percent = int(100 * min(max(fraction, 0.0), 1.0))
        shown_name, shown = self.last
        if name == shown_name and (percent == shown or (percent - shown < self.step and percent < 100)):
            return
        self.last = (name, percent)
        print(f"sssbake: {name} {percent}%", file=self.stream, flush=True)
