"""The sweep's progress on stderr: a bar for all runs (done, failed, left, time left) and one per node (its runs,
how many it is running, its runs per minute)."""
import sys
import time


class Progress:
    def __init__(self, total, nodes, enabled):
        from tqdm import tqdm
        self.tqdm = tqdm
        self.enabled = enabled
        self.total = total
        self.nodes = nodes  # node id -> {address, ...}
        self.started = time.monotonic()
        self.bar = tqdm(total=total, unit="run", disable=not enabled, file=sys.stderr, dynamic_ncols=True,
                        desc="all runs", position=0)
        self.failed = 0
        self.node_bars = {}
        self.running = {}  # node id -> the cells running there
        for node in nodes:
            self._node_bar(node)

    def _node_bar(self, node):
        if node not in self.node_bars:
            address = self.nodes.get(node, {}).get("address", "?")
            self.node_bars[node] = self.tqdm(total=self.total, unit="run", disable=not self.enabled,
                                             file=sys.stderr, dynamic_ncols=True, position=len(self.node_bars) + 1,
                                             desc="node %s %s" % (address, node[:8]), leave=True)
            self.running[node] = set()
        return self.node_bars[node]

    def began(self, index, node):
        for cells in self.running.values():
            cells.discard(index)  # run again elsewhere: its former node was lost
        self._node_bar(node)
        self.running[node].add(index)
        self._describe(node)

    def ended(self, index, node, status):
        for cells in self.running.values():
            cells.discard(index)
        self.failed += status != "pass"
        self.bar.update(1)
        self.bar.set_postfix_str("failed %d, left %d" % (self.failed, self.total - self.bar.n))
        if node:
            self._node_bar(node).update(1)
            self._describe(node)

    def lost(self, node):
        if node in self.node_bars:
            self.running[node].clear()
            self.node_bars[node].set_postfix_str("lost")

    def _describe(self, node):
        bar = self.node_bars[node]
        minutes = (time.monotonic() - self.started) / 60
        pace = bar.n / minutes if minutes else 0
        bar.set_postfix_str("running %d, %.0f runs/min" % (len(self.running[node]), pace))

    def refresh(self):
        for bar in [self.bar] + list(self.node_bars.values()):
            bar.refresh()

    def close(self):
        for bar in list(self.node_bars.values()) + [self.bar]:
            bar.close()
