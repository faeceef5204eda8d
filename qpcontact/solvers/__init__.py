"""The methods: what a method is (``method``), the one registry (``registry``),
the pivoting methods, the QP backends, the load trace.  Each provider declares
its methods in a ``specs()`` function and never imports the registry."""
