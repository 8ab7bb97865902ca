// Tables whose columns sort on a click of their header and whose rows answer hovering: plain DOM, no library.

// columns: [{key, label, title, format(value, row) -> text}]; rows: objects holding each column's key. A click on a
// header sorts by that column (again: the other way); numbers sort as numbers, text as text, and a missing value
// (null, undefined, NaN) goes last either way. options.onHover(row | null) is called as the pointer enters or
// leaves a row; options.rowKey(row) names a row (its <tr data-key>).
function sortableTable(columns, rows, options) {
  options = options || {};
  const table = document.createElement("table");
  table.className = "record-table sortable";
  const head = table.createTHead().insertRow(), body = table.createTBody();
  let sortKey = null, ascending = true;
  const missing = v => v === null || v === undefined || (typeof v === "number" && Number.isNaN(v));
  function compare(a, b) {
    const x = a[sortKey], y = b[sortKey];
    if (missing(x) || missing(y)) return missing(x) - missing(y);  // missing last, whatever the order
    const c = typeof x === "number" && typeof y === "number" ? x - y : String(x).localeCompare(String(y));
    return ascending ? c : -c;
  }
  function fill() {
    body.textContent = "";
    const order = sortKey === null ? rows.slice() : rows.slice().sort(compare);
    for (const r of order) {
      const tr = body.insertRow();
      if (options.rowKey) tr.dataset.key = options.rowKey(r);
      for (const c of columns) {
        const v = r[c.key];
        tr.insertCell().textContent = c.format ? c.format(v, r) : (missing(v) ? "—" : String(v));
      }
      tr.addEventListener("mouseenter", () => { tr.classList.add("hover"); if (options.onHover) options.onHover(r); });
      tr.addEventListener("mouseleave", () => { tr.classList.remove("hover"); if (options.onHover) options.onHover(null); });
    }
  }
  for (const c of columns) {
    const th = document.createElement("th");
    th.textContent = c.label;
    th.dataset.key = c.key;
    if (c.title) th.title = c.title;
    th.addEventListener("click", () => {
      ascending = sortKey === c.key ? !ascending : true;
      sortKey = c.key;
      for (const other of head.cells) delete other.dataset.order;
      th.dataset.order = ascending ? "ascending" : "descending";
      fill();
    });
    head.append(th);
  }
  fill();
  return table;
}
