// The collapsible tree panel. Rows are created lazily (a node's children only when it is first
// expanded), so trees of any size open instantly. Every row is <li data-node="INDEX">, with a
// .toggle (expand/collapse) and a .label (select).

import { nodeColor } from './colors.js';
import { PROXY_NAMES } from './data.js';

export class TreePanel {
  /// `container`: element to fill; `nodes`: nodeTable(); `onSelect(index)`: called on a click.
  constructor(container, nodes, onSelect) {
    this.nodes = nodes;
    this.onSelect = onSelect;
    this.rows = new Map();
    this.selected = -1;
    const root = document.createElement('ul');
    container.appendChild(root);
    if (nodes.n > 0) root.appendChild(this.makeRow(0));
    container.addEventListener('click', (event) => this.handleClick(event));
  }

  makeRow(i) {
    const t = this.nodes;
    const li = document.createElement('li');
    li.dataset.node = String(i);
    const row = document.createElement('div');
    row.className = 'row';
    const toggle = document.createElement('span');
    toggle.className = 'toggle';
    toggle.textContent = t.left[i] >= 0 ? '▸' : '';
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = `rgb(${nodeColor(i).join(',')})`;
    const label = document.createElement('span');
    label.className = 'label';
    label.textContent = `#${i} · ${t.count[i]} pts · ${PROXY_NAMES[t.kind[i]] ?? '?'}${t.left[i] < 0 ? ' · leaf' : ''}`;
    row.append(toggle, swatch, label);
    li.appendChild(row);
    this.rows.set(i, li);
    return li;
  }

  handleClick(event) {
    const li = event.target.closest('li[data-node]');
    if (!li) return;
    const i = Number(li.dataset.node);
    if (event.target.classList.contains('toggle')) this.setOpen(i, !li.classList.contains('open'));
    else this.onSelect(i);
  }

  /// Expands or collapses node i's row (which must exist).
  setOpen(i, open) {
    const t = this.nodes, li = this.rows.get(i);
    if (!li || t.left[i] < 0) return;
    if (open && !li.querySelector(':scope > ul')) {
      const ul = document.createElement('ul');
      ul.append(this.makeRow(t.left[i]), this.makeRow(t.right[i]));
      li.appendChild(ul);
    }
    li.classList.toggle('open', open);
    li.querySelector(':scope > .row > .toggle').textContent = open ? '▾' : '▸';
  }

  /// Marks node i selected (-1: none), expanding its ancestors so its row is visible.
  select(i) {
    if (this.selected >= 0) this.rows.get(this.selected)?.classList.remove('selected');
    this.selected = i;
    if (i < 0) return;
    const path = [];
    for (let p = this.nodes.parent[i]; p >= 0; p = this.nodes.parent[p]) path.push(p);
    for (let k = path.length - 1; k >= 0; --k) this.setOpen(path[k], true);
    const li = this.rows.get(i);
    li.classList.add('selected');
    li.querySelector(':scope > .row').scrollIntoView({ block: 'nearest' });
  }
}
