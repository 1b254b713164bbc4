"""The learning path's defaults, in one place the command line can read without numpy."""

RADIUS = 0.1            # metres: an object's proximity sphere (Sec. II-C)
HYSTERESIS = 0.005      # metres beyond the radius before leaving counts
MIN_MOTION = 0.01       # metres: a stretch that moves the hand less is a pause, not an action
SMOOTHING = 0.05        # seconds: segmentation averages the hand's position over this window
RATE = 100.0            # samples per second of a simulated demonstration
NOISE = 0.001           # metres: standard deviation of a simulated hand's position noise
SPEED = 0.25            # metres per second: the average speed of a long simulated motion
BASES = 30              # basis functions of a motion primitive per segment
MAX_BASES = 1000        # more is memory, not accuracy
MAX_RATE = 10_000.0     # samples per second a simulated demonstration may ask for
MAX_DEMO_BYTES = 256 * 1024 * 1024   # a 3-minute recording at 1 kHz with 5 objects is about 40 MB
