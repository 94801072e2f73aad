"""Sun position maths (:mod:`en17037cli.sun.position`) behind the sunlight engine."""
