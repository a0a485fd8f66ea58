"""The fork server's preload: importing this module warms the server, once per session.

multiprocessing's fork server only imports the modules of its preload list, so the
call to :func:`vhfit._warm.warm_up` is this module's body. Nothing in vhfit imports
it; :func:`vhfit._pools.get_context` names it in the preload list.
"""

from vhfit._warm import warm_up

warm_up()
