"""The defaults and limits a user can name, in one module the command line reads without
loading what they limit (`schemalog --help` imports no engine, no sympy, no numpy).

Each owning module takes its values from here: tree.py its depth and size limits, verify.py
its state limit, and so on, so that a default is written once.
"""

# Reading and instantiating knowledge (logic/parse.py, task/tree.py)
MAX_BYTES = 16 * 1024 * 1024  # lark reads ~0.45 MB/s: refuse what would take minutes
MAX_DEPTH = 256               # the deepest task tree instantiated
MAX_NODES = 2_000_000         # the largest task tree instantiated

# The process (cli/limits.py)
MEMORY_FRACTION = 0.5         # of physical memory: the default ceiling on the memory one run may use
MEMORY_ENV = "SCHEMALOG_MAX_MEMORY"   # the environment's ceiling (a size, or off), under --max-memory
MIN_TIMEOUT = 0.001           # seconds: --timeout's timer has microseconds, and below one it would not start
MAX_TIMEOUT = 365 * 24 * 3600 # seconds: setitimer overflows past the platform's time_t
MIN_MEMORY = 64 * 2**20       # a smaller ceiling would stop Python and the engine from starting

# The engine (logic/engine.py)
MAX_STEPS = 10_000_000        # resolution steps one query may take
MAX_INTEGER_BITS = 1 << 23    # bits in one integer result (~1 MB, 2.5 million digits): `is` raises
                              # resource_error(stack) past it, as swipl does past its 1 GB stack,
                              # before computing (2**10000000000 would never return); such an
                              # integer prints in ~1 s, and multiplying two takes ~0.05 s

# Compression (task/compress.py, task/conditions.py)
PROPAGATE_MODES = ("none", "pre", "full")
SYMPY_BUDGET = 8              # variables; sympy's simplify_logic costs ~0.3 s at 8
MAX_SYMPY_BUDGET = 12         # its cost doubles per variable: 16 ran for over 15 minutes

# Execution and verification (run/execute.py, run/verify.py)
SELECTORS = ("incremental", "scan")
RECOVERIES = ("decompress", "resume")   # what a failure inside a merged leaf does (the first is the default)
RETRIES = 2                   # a failed command is retried this many times, then inhibited
MAX_STATES = 50_000           # states explored per tree before verify stops (no proof)
WORK_PER_STATE = 1_000        # condition tests and state atoms copied per state of --max-states: verify
                              # stops (no proof) past max_states * this, so the limit bounds time too
MAX_SAMPLE = 1_000_000        # verify --sample RUNS at most
JITTER = 0.05                 # metres per coordinate that `run --seed` moves a scene's objects

# Generated tasks (evaluate/generate.py)
RD_TOLERANCE = 0.05           # how close the achieved reduction degree must come to the requested one

# Learning from demonstration (learn/)
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
MAX_NOISE = 0.01        # metres: noisier, a simulated hand would jump faster than learn accepts
MAX_JITTER = 1.0        # metres: a simulated object moved farther leaves the robot's reach
MAX_SIMULATED = 1_000_000   # samples of a simulated demonstration (about 200 MB of CSV)
MAX_DEMO_BYTES = 256 * 1024 * 1024   # a 3-minute recording at 1 kHz with 5 objects is about 40 MB
