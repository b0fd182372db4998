"""External control over zenoh: protocol, master-side bridge, controller client and examples.

* :mod:`~orchestrator.control.protocol` - key expressions, manifest, binary frames (versioned);
* :mod:`~orchestrator.control.session` - zenoh sessions (loopback, no multicast by default);
* :mod:`~orchestrator.control.bridge` - the master side: lock-step and real-time exchange,
  validation, fallbacks, statistics;
* :mod:`~orchestrator.control.client` - :class:`Controller`, to write a controller in a few lines;
* :mod:`~orchestrator.control.examples` - passive, reactive, latching and velocity-tracking laws
  (``wec-cosim controller NAME``).

The wire protocol is specified in ``docs/control.md``; any zenoh binding can implement a
controller from that page alone.
"""
