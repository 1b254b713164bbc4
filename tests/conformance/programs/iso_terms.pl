% ISO term inspection, construction and comparison (ISO 8.2-8.5), cyclic terms included.
p(1).
