"""The hand as a local service: other programs drive it over HTTP and a WebSocket, and a
page serves people (``gestplay serve``). ``core`` holds the rules without HTTP (what a
request may say, the order it becomes, the events and the pose as JSON); ``guard`` who
may ask; ``http`` the aiohttp edge and ``server`` its thread, the modules that import
the server (the optional extra ``serve``); ``work`` a request's compile work off the
event loop; ``allowance`` the sounds a request may make; ``page.html`` the page."""
